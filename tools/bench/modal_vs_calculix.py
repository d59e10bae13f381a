"""SOL 103 speed benchmark: paraflex against CalculiX on the same solid mesh and thread count.

Usage (from the repository root):

    .venv/bin/python tools/bench/modal_vs_calculix.py [--dofs N] [--modes 24] [--threads 1|2]
        [--only paraflex|calculix] [--paraflex BIN] [--workdir DIR] [--keep]

Generates a steel cantilever block 1.0 x 0.2 x 0.05 m of nx x ny x nz eight-node hexahedra
(near-cubic elements, the smallest mesh with 3 * nodes >= N; N defaults to 300,000, use
``--dofs 30000`` for a quick run), clamped (1, 2, 3) on the face x = 0, as

* a Nastran deck (free field: GRID, CHEXA, PSOLID, MAT1, SPC1, EIGRL ND, PARAM,COUPMASS,1), and
* a CalculiX .inp (C3D8I, *FREQUENCY with the same number of modes, *NODE FILE U),

with the same coordinate strings in both, in a fresh temp directory (``--workdir``, default /tmp;
removed afterwards unless ``--keep``). Both codes run one after the other under
``/usr/bin/time -v`` with the same thread count (ccx: OMP_NUM_THREADS, CCX_NPROC_STIFFNESS,
CCX_NPROC_EQUATION_SOLVER; paraflex: RAYON_NUM_THREADS) and write their mode shapes (ccx .frd,
paraflex HDF5). The script prints one table: wall time, CPU time, peak RSS, per-mode frequencies
and relative differences (sorted lists compared index by index), and the time ratio
paraflex / CalculiX.

CalculiX frequencies come from the ``E I G E N V A L U E   O U T P U T`` table of its .dat;
paraflex's from ``/results/1/modal/frequency_hz`` of its HDF5 file (h5py), or else from the
frequency table it prints. When the paraflex binary cannot run SOL 103 yet, the paraflex row says
so and the CalculiX side still runs. Not a test; generated files are not committed.
"""
from __future__ import annotations

import argparse
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from paraflex_tools.cards import card, free_cards
from paraflex_tools.results import modal_frequencies
from paraflex_tools.runner import default_binary

ROOT = Path(__file__).resolve().parents[2]
CCX = shutil.which("ccx") or "/usr/bin/ccx"
TIME = "/usr/bin/time"

# geometry (m) and steel (SI)
LX, LY, LZ = 1.0, 0.2, 0.05
E, NU, RHO = 210.0e9, 0.3, 7850.0


# --------------------------------------------------------------------------------------------
# mesh
# --------------------------------------------------------------------------------------------


def choose_mesh(dofs: int) -> tuple[int, int, int]:
    """Smallest near-cubic nx x ny x nz (proportional to 1.0 : 0.2 : 0.05) with 3 * nodes >= dofs."""
    s = 0.25
    while True:
        nx, ny, nz = max(2, round(LX / LZ * s)), max(1, round(LY / LZ * s)), max(1, round(s))
        if 3 * (nx + 1) * (ny + 1) * (nz + 1) >= dofs:
            return nx, ny, nz
        s *= 1.002


def real_str(v: np.ndarray) -> list[str]:
    """Coordinates as strings valid both as Nastran reals (always a decimal point) and for ccx."""
    out = []
    for x in v.tolist():
        s = "%.12g" % x
        if "e" in s:
            m, e = s.split("e")
            s = (m if "." in m else m + ".") + "e" + e
        elif "." not in s:
            s += "."
        out.append(s)
    return out


@dataclass
class Mesh:
    nx: int
    ny: int
    nz: int
    coords: list[tuple[str, str, str]] = field(repr=False)  # per node, ids 1..n in order
    hexes: np.ndarray = field(repr=False)  # (ne, 8) node ids
    clamp: np.ndarray = field(repr=False)  # node ids on x = 0

    @property
    def nodes(self) -> int:
        return (self.nx + 1) * (self.ny + 1) * (self.nz + 1)

    @property
    def elements(self) -> int:
        return self.nx * self.ny * self.nz


def build_mesh(nx: int, ny: int, nz: int) -> Mesh:
    xs = real_str(np.arange(nx + 1) * (LX / nx))
    ys = real_str(np.arange(ny + 1) * (LY / ny))
    zs = real_str(np.arange(nz + 1) * (LZ / nz))
    coords = [(xs[i], ys[j], zs[k]) for k in range(nz + 1) for j in range(ny + 1) for i in range(nx + 1)]

    def nid(i, j, k):
        return 1 + i + j * (nx + 1) + k * (nx + 1) * (ny + 1)

    k, j, i = np.meshgrid(np.arange(nz), np.arange(ny), np.arange(nx), indexing="ij")
    i, j, k = i.ravel(), j.ravel(), k.ravel()
    hexes = np.column_stack([nid(i, j, k), nid(i + 1, j, k), nid(i + 1, j + 1, k), nid(i, j + 1, k),
                             nid(i, j, k + 1), nid(i + 1, j, k + 1), nid(i + 1, j + 1, k + 1), nid(i, j + 1, k + 1)])
    kk, jj = np.meshgrid(np.arange(nz + 1), np.arange(ny + 1), indexing="ij")
    clamp = nid(0, jj.ravel(), kk.ravel())
    return Mesh(nx, ny, nz, coords, hexes.astype(np.int64), np.sort(clamp).astype(np.int64))


# --------------------------------------------------------------------------------------------
# writers
# --------------------------------------------------------------------------------------------


def write_nastran(mesh: Mesh, modes: int, path: Path, spc456: bool) -> None:
    head = f"""\
$ paraflex SOL 103 speed benchmark: steel cantilever {LX} x {LY} x {LZ} m,
$ {mesh.nx} x {mesh.ny} x {mesh.nz} CHEXA, {mesh.nodes} grids, clamped (123) at x = 0.
$ Written by tools/bench/modal_vs_calculix.py (CalculiX twin: ccx_bench.inp, C3D8I).
SOL 103
CEND
TITLE = paraflex vs CalculiX modal benchmark {mesh.nx}x{mesh.ny}x{mesh.nz}
METHOD = 1
SPC = 1
BEGIN BULK
$ coupled (consistent) mass, as CalculiX uses
"""
    grids = ((n, None, x, y, z) for n, (x, y, z) in enumerate(mesh.coords, start=1))
    hexes = np.column_stack([np.arange(1, mesh.elements + 1), np.ones(mesh.elements, int), mesh.hexes])
    cl = mesh.clamp.tolist()
    with open(path, "w", newline="\n") as f:
        f.write(head)
        f.write(card("PARAM", "COUPMASS", 1))
        f.write(card("EIGRL", 1, None, None, modes))
        f.write(card("MAT1", 1, E, None, NU, RHO))
        f.write(card("PSOLID", 1, 1))
        f.write(free_cards("GRID", grids))
        f.write(free_cards("CHEXA", hexes.tolist()))
        f.write(free_cards("SPC1", ((1, 123, *cl[a:a + 6]) for a in range(0, len(cl), 6))))
        if spc456:
            f.write("$ rotations of solid-only grids have no stiffness: fixed here explicitly instead of by AUTOSPC\n")
            f.write(card("SPC1", 1, 456, 1, "THRU", mesh.nodes))
        f.write("ENDDATA\n")


def write_inp(mesh: Mesh, modes: int, path: Path, element: str) -> None:
    h = np.column_stack([np.arange(1, mesh.elements + 1), mesh.hexes]).tolist()
    cl = mesh.clamp.tolist()
    with open(path, "w", newline="\n") as f:
        f.write(f"** paraflex SOL 103 speed benchmark, CalculiX twin of bench.dat (Nastran) ({element}, same mesh)\n")
        f.write("*NODE, NSET=NALL\n")
        f.write("".join([f"{n}, {x}, {y}, {z}\n" for n, (x, y, z) in enumerate(mesh.coords, start=1)]))
        f.write(f"*ELEMENT, TYPE={element}, ELSET=EALL\n")
        f.write("".join(["%d, %d, %d, %d, %d, %d, %d, %d, %d\n" % tuple(r) for r in h]))
        f.write("*NSET, NSET=CLAMP\n")
        f.write("".join([", ".join(map(str, cl[a:a + 16])) + "\n" for a in range(0, len(cl), 16)]))
        f.write(f"*MATERIAL, NAME=STEEL\n*ELASTIC\n{E:.6e}, {NU}\n*DENSITY\n{RHO}\n")
        f.write("*SOLID SECTION, ELSET=EALL, MATERIAL=STEEL\n")
        f.write("*BOUNDARY\nCLAMP, 1, 3\n")
        f.write(f"*STEP\n*FREQUENCY, SOLVER=SPOOLES\n{modes}\n*NODE FILE\nU\n*END STEP\n")


# --------------------------------------------------------------------------------------------
# running and parsing
# --------------------------------------------------------------------------------------------


@dataclass
class Run:
    code: str
    threads: int
    ok: bool = False
    note: str = ""
    wall_s: float = math.nan
    cpu_s: float = math.nan
    rss_mb: float = math.nan
    freqs: list[float] = field(default_factory=list)
    equations: int | None = None  # size of the system the code solved, when it says
    details: list[str] = field(default_factory=list)
    load: float = math.nan  # 1-min load average when the run started (other work on the machine)


def timed(cmd: list[str], cwd: Path, env: dict, log: Path) -> tuple[int, float, float, float, str, float]:
    """Run cmd under /usr/bin/time -v; return (rc, wall s, user+sys s, max RSS MB, stdout+stderr, load avg)."""
    tfile = log.with_suffix(".time")
    load = os.getloadavg()[0]
    t0 = time.perf_counter()
    with open(log, "w") as out:
        p = subprocess.run([TIME, "-v", "-o", str(tfile), *cmd], cwd=cwd, env=env, stdout=out, stderr=subprocess.STDOUT)
    wall = time.perf_counter() - t0
    log.with_suffix(".load").write_text(f"{load}\n")
    tv = tfile.read_text() if tfile.exists() else ""

    def grab(label):
        for line in tv.splitlines():
            if line.strip().startswith(label):
                return line.rsplit(": ", 1)[1].strip()
        return None

    w = grab("Elapsed (wall clock) time")
    if w:
        parts = [float(x) for x in w.split(":")]
        wall = sum(x * 60 ** (len(parts) - 1 - n) for n, x in enumerate(parts))
    cpu = float(grab("User time") or "nan") + float(grab("System time") or "nan")
    rss = float(grab("Maximum resident set size") or "nan") / 1024.0
    return p.returncode, wall, cpu, rss, log.read_text(errors="replace"), load


def thread_env(threads: int) -> dict:
    env = dict(os.environ)
    env.update({"OMP_NUM_THREADS": str(threads), "CCX_NPROC_STIFFNESS": str(threads),
                "CCX_NPROC_EQUATION_SOLVER": str(threads), "CCX_NPROC_RESULTS": str(threads),
                "RAYON_NUM_THREADS": str(threads)})
    return env


def ccx_eigensolver() -> str:
    """What this ccx links for *FREQUENCY: ARPACK plus SPOOLES and/or PARDISO (from the binary)."""
    try:
        libs = subprocess.run(["ldd", CCX], capture_output=True, text=True).stdout
        strs = subprocess.run(["strings", CCX], capture_output=True, text=True).stdout
    except OSError:
        return "unknown"
    arpack = "ARPACK" if "libarpack" in libs else "ARPACK (static?)"
    pardiso = not ("the PARDISO library is not linked" in strs) and ("mkl" in libs or "pardiso" in libs.lower())
    spooles_mt = "CCX_NPROC_EQUATION_SOLVER" in strs
    blas = "reference BLAS" if "/blas/libblas" in (os.path.realpath("/lib/x86_64-linux-gnu/libblas.so.3")) else os.path.realpath("/lib/x86_64-linux-gnu/libblas.so.3")
    solver = "PARDISO" if pardiso else "SPOOLES"
    mt = "multi-threaded (USE_MT)" if spooles_mt else "single-threaded (built without USE_MT: CCX_NPROC_EQUATION_SOLVER is ignored)"
    return f"{arpack} shift-invert with {solver} ({solver} {mt}; PARDISO {'linked' if pardiso else 'not linked'}; {blas})"


def ccx_version() -> str:
    try:
        p = subprocess.run([CCX, "-v"], capture_output=True, text=True)
    except OSError:
        return f"CalculiX not found at {CCX}"
    m = re.search(r"Version\s+(\S+)", p.stdout + p.stderr)
    return f"CalculiX {m.group(1)}" if m else "CalculiX ?"


def parse_ccx_dat(dat: Path) -> list[float]:
    text = dat.read_text()
    k = text.find("E I G E N V A L U E   O U T P U T")
    if k < 0:
        return []
    num = r"([-+]?\d*\.?\d+(?:[EeDd][-+]?\d+)?)"
    pat = re.compile(rf"^\s*(\d+)\s+{num}\s+{num}\s+{num}\s+{num}\s*$")
    out, started = [], False
    for line in text[k:].splitlines()[1:]:
        m = pat.match(line)
        if m:
            started = True
            out.append(float(m.group(4)))
        elif started and line.strip():
            break
    return out


def read_timed(work: Path, name: str) -> tuple[int, float, float, float, str, float]:
    """The numbers timed() measured in an earlier run whose work dir was kept (--calculix-from)."""
    tv = (work / f"{name}.time").read_text()

    def grab(label):
        for line in tv.splitlines():
            if line.strip().startswith(label):
                return line.rsplit(": ", 1)[1].strip()
        return "nan"

    parts = [float(x) for x in grab("Elapsed (wall clock) time").split(":")]
    wall = sum(x * 60 ** (len(parts) - 1 - n) for n, x in enumerate(parts))
    m = re.search(r"Exit status:\s*(\d+)", tv)
    rc = int(m.group(1)) if m else 0
    load = float((work / f"{name}.load").read_text()) if (work / f"{name}.load").exists() else math.nan
    return (rc, wall, float(grab("User time")) + float(grab("System time")),
            float(grab("Maximum resident set size")) / 1024.0, (work / f"{name}.log").read_text(errors="replace"), load)


def run_calculix(work: Path, threads: int, reuse: Path | None = None) -> Run:
    r = Run("CalculiX", threads)
    if reuse is not None:
        if (reuse / "ccx_bench.inp").read_bytes() != (work / "ccx_bench.inp").read_bytes():
            r.note = f"--calculix-from {reuse}: its ccx_bench.inp differs from this run's (other --dofs/--modes?)"
            return r
        if f"Using up to {threads} cpu(s) for spooles" not in (reuse / "ccx.log").read_text(errors="replace"):
            r.note = f"--calculix-from {reuse}: that run did not use {threads} thread(s)"
            return r
        rc, r.wall_s, r.cpu_s, r.rss_mb, log, r.load = read_timed(reuse, "ccx")
        work = reuse
        r.details.append(f"(measured earlier, in {reuse})")
    else:
        rc, r.wall_s, r.cpu_s, r.rss_mb, log, r.load = timed([CCX, "-i", "ccx_bench"], work, thread_env(threads), work / "ccx.log")
    if rc != 0 or "*ERROR" in log:
        r.note = f"ccx failed (rc {rc}): " + " | ".join(l.strip() for l in log.splitlines() if "ERROR" in l)[:300]
        return r
    r.freqs = parse_ccx_dat(work / "ccx_bench.dat")
    m = re.search(r"number of equations\s*\n\s*(\d+)", log)
    r.equations = int(m.group(1)) if m else None
    for pat in (r"Using up to \d+ cpu\(s\) for the symmetric stiffness/mass contributions\.",
                r"Factoring the system of equations using the [^\n]*", r"Using up to \d+ cpu\(s\) for spooles\.", r"Total CalculiX Time:\s*\S+"):
        m = re.search(pat, log)
        if m:
            r.details.append(m.group(0).strip())
    r.ok = len(r.freqs) > 0
    if not r.ok:
        r.note = "no eigenvalue table in ccx_bench.dat"
    return r


def parse_paraflex_stdout(text: str) -> list[float]:
    out = []
    pat = re.compile(r"^\s+(\d+)\s+([-+]?\d\.\d+E[-+]\d+)\s+([-+]?\d\.\d+E[-+]\d+)\s+(\S+)\s*$")
    for line in text.splitlines():
        m = pat.match(line)
        if m and int(m.group(1)) == len(out) + 1:
            out.append(float(m.group(2)))
    return out


def run_paraflex(work: Path, threads: int, binary: Path) -> Run:
    r = Run("paraflex", threads)
    if not binary.exists():
        r.note = f"paraflex SOL 103 not available yet (no binary at {binary}; build with cargo build --release)"
        return r
    h5 = work / "bench_paraflex.h5"
    rc, r.wall_s, r.cpu_s, r.rss_mb, log, r.load = timed([str(binary), "run", "bench.dat", "-o", str(h5)], work,
                                                  thread_env(threads), work / "paraflex.log")
    if rc != 0:
        if rc == 3 or "is not available" in log:
            r.note = "paraflex SOL 103 not available yet (" + next(
                (l.strip() for l in log.splitlines() if "not available" in l), f"exit code {rc}") + ")"
        else:
            r.note = f"paraflex failed (exit code {rc}): " + " | ".join(
                l.strip() for l in log.splitlines() if "error" in l.lower())[:400]
        return r
    try:
        r.freqs = [float(x) for x in modal_frequencies(h5)]
    except Exception as e:  # noqa: BLE001
        r.freqs = parse_paraflex_stdout(log)
        r.details.append(f"frequencies from stdout ({type(e).__name__}: {e})")
    m = re.search(r"f-set (\d+) DOFs", log)
    r.equations = int(m.group(1)) if m else None
    in_resources = False
    for line in log.splitlines():
        if line.startswith("resources per phase"):
            in_resources = True
        elif in_resources and not line.startswith("  "):
            in_resources = False
        if in_resources or line.startswith("timings:") or "Sturm" in line or "Lanczos:" in line:
            r.details.append(line.rstrip() if in_resources else line.strip())
    r.ok = len(r.freqs) > 0
    if not r.ok:
        r.note = "paraflex ran but no frequencies were found (HDF5 /results/1/modal/frequency_hz nor stdout)"
    return r


# --------------------------------------------------------------------------------------------
# report
# --------------------------------------------------------------------------------------------


def fmt(x: float, spec: str) -> str:
    return "-" if x is None or (isinstance(x, float) and math.isnan(x)) else format(x, spec)


def report(mesh: Mesh, modes: int, runs: list[Run], solver: str, version: str, element: str) -> None:
    dofs = 3 * mesh.nodes
    free = 3 * (mesh.nodes - len(mesh.clamp))
    print()
    print(f"mesh: {mesh.nx} x {mesh.ny} x {mesh.nz} hexahedra ({mesh.elements} elements), {mesh.nodes} nodes, "
          f"{dofs} DOFs (3 per node), {free} free after the clamp; {modes} modes")
    print(f"CalculiX: {version}, {element}, eigensolver: {solver}")
    print()
    print(f"{'code':<10} {'threads':>7} {'DOFs':>8} {'solved eqs':>10} {'wall s':>9} {'cpu s':>9} {'peak RSS MB':>11} {'load':>5}  note")
    for r in runs:
        print(f"{r.code:<10} {r.threads:>7} {dofs:>8} {fmt(r.equations, 'd') if r.equations else '-':>10} "
              f"{fmt(r.wall_s, '.2f'):>9} {fmt(r.cpu_s, '.2f'):>9} {fmt(r.rss_mb, '.0f'):>11} {fmt(r.load, '.1f'):>5}  {r.note}")
        for d in r.details:
            print(f"{'':<10}   {d}")
    ccx = next((r for r in runs if r.code == "CalculiX"), None)
    pfx = next((r for r in runs if r.code == "paraflex"), None)
    print()
    if ccx and ccx.ok and pfx and pfx.ok:
        a, b = sorted(ccx.freqs), sorted(pfx.freqs)
        n = min(len(a), len(b), modes)
        print(f"{'mode':>4} {'CalculiX Hz':>14} {'paraflex Hz':>14} {'rel diff':>10}")
        rel = []
        for k in range(n):
            d = (b[k] - a[k]) / a[k]
            rel.append(abs(d))
            print(f"{k + 1:>4} {a[k]:>14.6f} {b[k]:>14.6f} {d:>10.2e}")
        if len(a) != len(b):
            print(f"  mode counts differ: CalculiX {len(a)}, paraflex {len(b)}")
        print(f"max |rel diff| over {n} modes: {max(rel):.2e}")
        print(f"time ratio paraflex / CalculiX ({ccx.threads} thread(s)): {pfx.wall_s / ccx.wall_s:.3f} "
              f"(paraflex {pfx.wall_s:.2f} s, CalculiX {ccx.wall_s:.2f} s); "
              f"peak memory ratio {pfx.rss_mb / ccx.rss_mb:.3f}")
        print(f"CPU time ratio paraflex / CalculiX (user + sys; robust to other load on the machine): "
              f"{pfx.cpu_s / ccx.cpu_s:.3f} (paraflex {pfx.cpu_s:.2f} s, CalculiX {ccx.cpu_s:.2f} s)")
    else:
        for r in (ccx, pfx):
            if r and r.ok:
                print(f"{r.code} frequencies (Hz): " + ", ".join(f"{f:.6f}" for f in r.freqs))
        if pfx and not pfx.ok:
            print(f"no comparison: {pfx.note}")
        if ccx and not ccx.ok:
            print(f"no comparison: {ccx.note}")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--dofs", type=int, default=300_000, help="minimum 3 * nodes (default 300000; 30000 = quick)")
    ap.add_argument("--modes", type=int, default=24)
    ap.add_argument("--threads", type=int, choices=[1, 2], default=1)
    ap.add_argument("--only", choices=["paraflex", "calculix"], help="run one code only")
    ap.add_argument("--paraflex", type=Path, default=None, help="paraflex binary (default: $PARAFLEX, "
                    "$CARGO_TARGET_DIR/release, target/release)")
    ap.add_argument("--ccx-element", default="C3D8I", choices=["C3D8I", "C3D8"],
                    help="CalculiX element (C3D8I = paraflex's CHEXA formulation; C3D8 only for experiments)")
    ap.add_argument("--autospc", action="store_true",
                    help="leave the rotations of the grids to paraflex's AUTOSPC (default: SPC1 456 on every grid; "
                         "same physics, works around paraflex writing the AUTOSPC list as one HDF5 attribute, which "
                         "fails above 64 kB, i.e. beyond ~2,000 solid grids)")
    ap.add_argument("--calculix-from", type=Path, default=None, metavar="DIR",
                    help="take the CalculiX numbers from an earlier run's kept work dir (same --dofs, --modes, "
                         "--threads; checked) instead of running ccx again")
    ap.add_argument("--workdir", type=Path, default=Path(tempfile.gettempdir()))
    ap.add_argument("--keep", action="store_true", help="keep the work directory (decks, logs, results)")
    a = ap.parse_args()

    nx, ny, nz = choose_mesh(a.dofs)
    t0 = time.perf_counter()
    mesh = build_mesh(nx, ny, nz)
    work = Path(tempfile.mkdtemp(prefix=f"modal_bench_{3 * mesh.nodes}_", dir=a.workdir))
    write_nastran(mesh, a.modes, work / "bench.dat", not a.autospc)
    write_inp(mesh, a.modes, work / "ccx_bench.inp", a.ccx_element)
    print(f"work dir {work}: wrote bench.dat ({(work / 'bench.dat').stat().st_size / 1e6:.1f} MB) and ccx_bench.inp "
          f"({(work / 'ccx_bench.inp').stat().st_size / 1e6:.1f} MB) in {time.perf_counter() - t0:.1f} s", flush=True)

    runs = []
    try:
        if a.only != "paraflex":
            print(f"running CalculiX ({a.threads} thread(s)) ...", flush=True)
            runs.append(run_calculix(work, a.threads, a.calculix_from))
        if a.only != "calculix":
            binary = a.paraflex or default_binary()
            print(f"running paraflex {binary} ({a.threads} thread(s)) ...", flush=True)
            runs.append(run_paraflex(work, a.threads, binary))
        report(mesh, a.modes, runs, ccx_eigensolver(), ccx_version(), a.ccx_element)
    finally:
        if a.keep:
            print(f"kept {work}")
        else:
            shutil.rmtree(work, ignore_errors=True)
    return 0 if all(r.ok for r in runs) else 1


if __name__ == "__main__":
    sys.exit(main())
