"""FRF speed against error on the blade scene: full direct (SOL 108) vs full modal (SOL 111) vs
pROM (SOL PROM once, then SOL 111 on the artifact).

Usage (from the repository root; paraflex built with ``cargo build --release``):

    .venv/bin/python tools/bench/frf_bench.py [--size test|medium|full] [--lines 100]
        [--fmax 500] [--modal-fmax 2000] [--paraflex BIN] [--workdir DIR] [--keep]

Mesh: ``test`` is the committed meshes/blade (761 grids); ``medium`` is generated into the work
directory by meshes/blade.py with twice the test divisions (about 4,000 grids); ``full`` needs
``make meshes-full`` (meshes/full/blade, 65,828 grids; the direct solve of that size needs a lot
of memory). Model: decks/blade/blade_ti_bolts.bdf (Ti Gr23 on four bolt springs), Rayleigh
alpha = 0.02, beta = 0.0005 (thesis Table 3.2). Inputs and outputs: T3 of the three ASET1 grids
(FRF input at mid-span, thesis Fig. 3.8); ``--lines`` equally spaced lines in (0, FMAX].

* direct: the reference (exact up to the sparse LU's round-off);
* modal: the EIGRL modes below ``--modal-fmax`` (no residual flexibility);
* pROM: E and rho +-40 % (as decks/blade/blade_prom_e_rho.dat: 5 samples, 15 modes, FMAX 500,
  ERRTOL 1e-3, static modes at the ASET1 grids), evaluated at the nominal point.

Prints wall time per run (the process, including reading and assembly) and the error
max_lines |H - H_direct| / max_lines |H_direct| over the 3 x 3 block, plus the median over
lines of the per-line relative error. Not a test; the work directory is removed unless --keep.
"""
from __future__ import annotations

import argparse
import importlib.util
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import h5py
import numpy as np

REPO = Path(__file__).resolve().parents[2]


def medium_mesh(out: Path) -> Path:
    """meshes/blade.py with twice the test divisions (spanwise 0.015 m)."""
    spec = importlib.util.spec_from_file_location("blade_mesh", REPO / "meshes" / "blade.py")
    blade = importlib.util.module_from_spec(spec)
    sys.modules["blade_mesh"] = blade
    spec.loader.exec_module(blade)
    blade.SIZES["medium"] = blade.Divisions(nose=2, box1=4, box2=4, trailing=6, thickness=4, ring=2,
                                           flange=2, span_length=0.015)
    blade.generate(out, "medium")
    return out


def run(binary: str, deck: Path, out: Path) -> float:
    start = time.perf_counter()
    p = subprocess.run([binary, "run", str(deck), "-o", str(out)], capture_output=True, text=True)
    wall = time.perf_counter() - start
    if p.returncode != 0:
        sys.exit(f"{deck.name} failed ({p.returncode}):\n{p.stdout}\n{p.stderr}")
    return wall


def read(path: Path, keep: list[str]) -> tuple[np.ndarray, np.ndarray]:
    """H restricted to the outputs and inputs named in `keep`, lines × outputs × inputs."""
    with h5py.File(path, "r") as f:
        g = f["results/1/frf"]
        hz = g["frequency_hz"][()]
        h = g["H"][()]
        outs = [s.decode() if isinstance(s, bytes) else s for s in g["outputs"][()]]
        ins = [s.decode() if isinstance(s, bytes) else s for s in g["inputs"][()]]
    return hz, h[:, [outs.index(k) for k in keep]][:, :, [ins.index(k) for k in keep]]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--size", choices=["test", "medium", "full"], default="test")
    ap.add_argument("--lines", type=int, default=100)
    ap.add_argument("--fmax", type=float, default=500.0)
    ap.add_argument("--modal-fmax", type=float, default=2000.0)
    ap.add_argument("--paraflex", default=str(REPO / "target" / "release" / "paraflex"))
    ap.add_argument("--workdir", type=Path, default=Path(tempfile.gettempdir()))
    ap.add_argument("--keep", action="store_true")
    args = ap.parse_args()
    work = Path(tempfile.mkdtemp(prefix="frf_bench_", dir=args.workdir))
    try:
        mesh = {"test": REPO / "meshes" / "blade", "full": REPO / "meshes" / "full" / "blade"}.get(args.size)
        if mesh is None:
            mesh = medium_mesh(work / "mesh")
        if not (mesh / "blade.bdf").exists():
            sys.exit(f"{mesh}/blade.bdf missing (make meshes-full for --size full)")
        rbe = (mesh / "blade_rbe.bdf").read_text()
        aset = next(line for line in rbe.splitlines() if line.startswith("ASET1")).split()[2:5]
        keep = [f"{g}:3" for g in aset]
        n_grids = sum(1 for line in (mesh / "blade.bdf").read_text().splitlines() if line.startswith("GRID"))
        model = (f"PARAM,ALPHA1,0.02\nPARAM,BETA1,0.0005\nINCLUDE '{REPO}/decks/blade/blade_ti_bolts.bdf'\n"
                 f"INCLUDE '{mesh}/blade.bdf'\nINCLUDE '{mesh}/blade_rbe.bdf'\n")
        df = args.fmax / args.lines
        freq = f"FREQ1,5,{df!r},{df!r},{args.lines - 1}\n"
        loads = (f"RLOAD1,7,8,,,20\nDAREA,8,{aset[0]},3,1.,{aset[1]},3,1.\nDAREA,8,{aset[2]},3,1.\n"
                 "TABLED1,20\n,0.,1.,1.E4,1.,ENDT\n")
        case = "FREQUENCY = 5\nDLOAD = 7\n"
        decks = {
            "direct": f"SOL 108\nCEND\n{case}BEGIN BULK\n{freq}{loads}{model}ENDDATA\n",
            "modal": f"SOL 111\nCEND\n{case}METHOD = 10\nBEGIN BULK\nEIGRL,10,,{args.modal_fmax!r}\n{freq}{loads}{model}ENDDATA\n",
            "prom_build": ("SOL PROM\nCEND\nPROM = 1\nBEGIN BULK\nPMPAR,1,E,E,1,69.624E9,162.456E9\n"
                           "PMPAR,2,RHO,RHO,1,2923.8,6822.2\nPMOR,1,5,15,500.,1.E-3,8\n,1\n"
                           f"{model}ENDDATA\n"),
            "prom_frf": (f"SOL 111\nCEND\nROM = '{work}/prom_build.h5'\nFREQUENCY = 5\nBEGIN BULK\n{freq}ENDDATA\n"),
        }
        times = {}
        for name, text in decks.items():
            deck = work / f"{name}.dat"
            deck.write_text(text)
            times[name] = run(args.paraflex, deck, work / f"{name}.h5")
            print(f"  {name}: {times[name]:.2f} s", file=sys.stderr)
        hz, ref = read(work / "direct.h5", keep)
        scale = np.abs(ref).max()
        print(f"blade --size {args.size}: {n_grids} grids, {args.lines} lines in (0, {args.fmax:g}] Hz, "
              f"inputs/outputs {', '.join(keep)}")
        print(f"| method | wall time [s] | max error (of max abs H) | median per-line error |")
        print(f"|---|---|---|---|")
        for name, label in [("direct", "full direct (SOL 108)"), ("modal", f"full modal (SOL 111, modes < {args.modal_fmax:g} Hz)"),
                            ("prom_frf", "pROM (SOL 111 on the artifact)")]:
            _, h = read(work / f"{name}.h5", keep)
            err = np.abs(h - ref).max() / scale
            per_line = np.abs(h - ref).max(axis=(1, 2)) / np.abs(ref).max(axis=(1, 2))
            t = f"{times[name]:.2f}" + (f" (+ {times['prom_build']:.2f} offline build)" if name == "prom_frf" else "")
            print(f"| {label} | {t} | {err:.1e} | {np.median(per_line):.1e} |")
    finally:
        if args.keep:
            print(f"kept {work}", file=sys.stderr)
        else:
            shutil.rmtree(work, ignore_errors=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())
