#!/usr/bin/env python3
"""Speed against error of the transient integrators on a pROM: the blade or the composite link
L2r (docs/performance.md "Transient integrators").

    .venv/bin/python tools/bench/transient_bench.py [--scene blade|link]
        [--dt 4e-4 2e-4 1e-4 5e-5] [--repeat 3] [--paraflex target/release/paraflex] [--keep DIR]

Builds the scene's pROM, writes a seeded band-limited random force (RMS 1 N,
tools/signals/make_signal.py) at its input DOF, and runs 1 s of SOL 112 with each TINTEG method
at several Δt. Error: max |y − y_ref| / max |y_ref| of the scene's output over the run, against
generalized-α ρ∞ = 1 (the trapezoidal rule) at Δt = 6.25e-6 s; the reference's own error is
≈ (ωΔt)²/12 relative phase per radian, far below the coarse runs'.

* ``blade``: decks/blade/blade_prom_e_rho.dat (E and ρ, 31 reduced DOFs) at its nominal point;
  force 10–200 Hz at grid 71 T3, output the 71:3 displacement.
* ``link``: decks/crossmodel/l2r_prom.dat (free-free L2r, THETA over [0, 45] deg, 4 samples)
  evaluated at THETA = 20 deg (PVAL); force 10–400 Hz (inside the pROM's 500 Hz band) at the
  distal motor axis 1000002 T3, output the drive-point accelerometer A1000002 (the free-free
  link's displacement drifts as a rigid body; its acceleration does not).

Time: wall time of the run's "pROM transient" step as printed by paraflex (reading the artifact,
the time loop and the output) and CPU time of the whole process (including start-up and writing
the file, ≈ 20 ms), best of --repeat runs each; on a loaded machine the CPU column is the steadier one.
"""
from __future__ import annotations

import argparse
import re
import resource
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

import h5py
import numpy as np

from paraflex_tools.results import transient_series
from paraflex_tools.runner import default_binary, run_checked

ROOT = Path(__file__).resolve().parents[2]
METHODS = [("BDF1", ""), ("BDF2", "TINTEG,1,BDF2\n"), ("GALPHA 0.8", "TINTEG,1,GALPHA,0.8\n"), ("GALPHA 1.0", "TINTEG,1,GALPHA,1.\n")]
STEPS = [4e-4, 2e-4, 1e-4, 5e-5]
T_END = 1.0


@dataclass
class Scene:
    """What the runs of one scene differ in."""
    title: str
    prom_deck: Path  # SOL PROM deck building the artifact
    grid: int  # force input: T3 of this grid
    band: tuple[float, float]  # force band [Hz]
    output: tuple[str, str]  # ("displacement", "grid:comp") or ("sensors", sensor name)
    pval: str = ""  # PVAL card (id 1); blank = nominal point


SCENES = {
    "blade": Scene("blade pROM", ROOT / "decks/blade/blade_prom_e_rho.dat", 71, (10.0, 200.0), ("displacement", "71:3")),
    "link": Scene("L2r pROM at THETA = 20 deg", ROOT / "decks/crossmodel/l2r_prom.dat", 1000002, (10.0, 400.0),
                  ("sensors", "S174"), "PVAL,1,THETA,20.\n"),
}


def deck(scene: Scene, rom: Path, csv: Path, dt: float, tinteg: str) -> str:
    n = int(round(T_END / dt))
    pval = "PVAL = 1\n" if scene.pval else ""
    return (f"SOL 112\nCEND\nROM = '{rom}'\n{pval}TSTEP = 1\nDLOAD = 7\nBEGIN BULK\nTSTEP,1,{n},{dt:.6e},1\n{tinteg}"
            f"TLOAD1,7,8,,,9\nDAREA,8,{scene.grid},3,1.\nTABLEF,9,'{csv}',time,force\n{scene.pval}ENDDATA\n")


def run(exe: Path, path: Path, out: Path) -> tuple[float, float]:
    """(wall time of the "pROM transient" step, CPU time of the whole process) in seconds."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    r = run_checked(path, out, exe)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    m = re.search(r"pROM transient ([0-9.]+) s", r.stdout)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return (float(m.group(1)) if m else float("nan")), cpu


def series(out: Path, output: tuple[str, str]) -> tuple[np.ndarray, np.ndarray]:
    with h5py.File(out, "r") as f:
        g = f["results/1/transient"]
        return g["time"][:], transient_series(g, *output)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--scene", choices=sorted(SCENES), default="blade")
    ap.add_argument("--paraflex", type=Path, default=default_binary())
    ap.add_argument("--dt", type=float, nargs="+", default=STEPS, help=f"time steps [s] (default {STEPS})")
    ap.add_argument("--repeat", type=int, default=3, help="runs per method and step; the table shows the best")
    ap.add_argument("--keep", type=Path, default=None, help="work directory to keep (default: a temp dir)")
    a = ap.parse_args()
    scene = SCENES[a.scene]
    work = a.keep or Path(tempfile.mkdtemp(prefix="paraflex_tr_bench_"))
    work.mkdir(parents=True, exist_ok=True)
    rom = work / f"{a.scene}_prom.h5"
    run_checked(scene.prom_deck, rom, a.paraflex)
    csv = work / "force.csv"
    subprocess.run([sys.executable, str(ROOT / "tools/signals/make_signal.py"), "random", "-o", str(csv), "--band", str(scene.band[0]), str(scene.band[1]),
                    "--rms", "1", "--seed", "7", "--duration", str(T_END), "--dt", "1e-4"], check=True, capture_output=True)
    ref_dt = 6.25e-6
    ref_deck = work / "ref.dat"
    ref_deck.write_text(deck(scene, rom, csv, ref_dt, "TINTEG,1,GALPHA,1.\n"))
    run(a.paraflex, ref_deck, work / "ref.h5")
    t_ref, u_ref = series(work / "ref.h5", scene.output)
    scale = np.abs(u_ref).max()
    print(f"{scene.title}, 1 s, random {scene.band[0]:g}-{scene.band[1]:g} Hz force at {scene.grid} T3; output {scene.output[1]} "
          f"({scene.output[0]}); reference GALPHA 1.0 at dt = {ref_dt:g} s; peak |y| = {scale:.3e}")
    print(f"{'method':<12}{'dt [s]':>10}{'steps':>8}{'rel. error':>12}{'wall [ms]':>11}{'CPU [ms]':>10}")
    for name, tinteg in METHODS:
        for dt in a.dt:
            path = work / f"run_{name.replace(' ', '_')}_{dt:g}.dat"
            path.write_text(deck(scene, rom, csv, dt, tinteg))
            out = work / "run.h5"
            times = [run(a.paraflex, path, out) for _ in range(a.repeat)]
            wall, cpu = min(w for w, _ in times), min(c for _, c in times)
            t, u = series(out, scene.output)
            stride = int(round(dt / ref_dt))
            err = np.abs(u - u_ref[::stride][: len(u)]).max() / scale
            print(f"{name:<12}{dt:>10.2e}{len(t) - 1:>8}{err:>12.2e}{1e3 * wall:>11.1f}{1e3 * cpu:>10.1f}")
            out.unlink()
    if a.keep is None:
        for p in work.iterdir():
            p.unlink()
        work.rmdir()


if __name__ == "__main__":
    main()
