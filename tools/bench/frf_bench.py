"""FRF speed against error on the blade and the composite link L2r: full direct (SOL 108) vs full
modal (SOL 111) vs pROM (SOL PROM once, then SOL 111 on the artifact).

Usage (from the repository root; paraflex built with ``cargo build --release``):

    .venv/bin/python tools/bench/frf_bench.py [--scene blade|link] [--size test|medium|full]
        [--lines 100] [--fmax 500] [--modal-fmax 2000] [--paraflex BIN] [--workdir DIR] [--keep]

Scenes:

* ``blade`` (default): mesh ``test`` is the committed meshes/blade (761 grids); ``medium`` is
  generated into the work directory by meshes/blade.py with twice the test divisions (about
  4,000 grids); ``full`` needs ``make meshes-full`` (meshes/full/blade, 65,828 grids; the direct
  solve of that size needs a lot of memory). Model: decks/blade/blade_ti_bolts.bdf (Ti Gr23 on
  four bolt springs), Rayleigh alpha = 0.02, beta = 0.0005 (thesis Table 3.2). Inputs and
  outputs: T3 of the three ASET1 grids (FRF input at mid-span, thesis Fig. 3.8). pROM: E and
  rho +-40 % (as decks/blade/blade_prom_e_rho.dat: 5 samples, 15 modes, FMAX 500, ERRTOL 1e-3,
  static modes at the ASET1 grids), evaluated at the nominal point.
* ``link``: the free-free composite link L2r of decks/crossmodel/l2r_common.bdf (test mesh
  meshes/robot/l2_composite.bdf, 6,402 free DOFs; only ``--size test``), [+-20]2s CFRP laminate,
  Rayleigh alpha = 1, beta = 1e-5. Inputs and outputs: T3 of the two motor axes 1000001 and
  1000002 (the ASET1 masters). pROM: THETA over [0, 45] deg as decks/crossmodel/l2r_prom.dat
  (4 samples, 16 modes, FMAX 500, ERRTOL 1e-3, attachment and rigid-body modes), evaluated at
  THETA = 20 deg (PVAL).

``--lines`` equally spaced lines in (0, FMAX]. direct is the reference (exact up to the sparse
LU's round-off); modal uses the EIGRL modes below ``--modal-fmax`` with paraflex's default
residual vectors of the load shapes (PARAM,RESVEC,YES; skipped on the free-free link), and
"modes only" the same modes with PARAM,RESVEC,NO.

Prints wall time per run (the process, including reading and assembly) and the error
max_lines |H - H_direct| / max_lines |H_direct| over the inputs x outputs block, plus the median
over lines of the per-line relative error. Not a test; the work directory is removed unless
--keep.
"""
from __future__ import annotations

import argparse
import importlib.util
import shutil
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from paraflex_tools import REPO
from paraflex_tools.results import read_frf
from paraflex_tools.runner import default_binary, run_checked


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
    return run_checked(deck, out, binary).seconds


def read(path: Path, keep: list[str]) -> tuple[np.ndarray, np.ndarray]:
    """H restricted to the outputs and inputs named in `keep`, lines × outputs × inputs."""
    frf = read_frf(path)
    h = frf.H[:, [frf.outputs.index(k) for k in keep]][:, :, [frf.inputs.index(k) for k in keep]]
    return frf.frequency_hz, h


@dataclass
class Scene:
    """What the four decks of one scene differ in."""
    title: str  # for the table's header line
    model: str  # bulk data of the full model (with its damping)
    keep: list[str]  # inputs = outputs, "grid:component"
    prom: str  # PMPAR and PMOR cards of the pROM build
    pval: str = ""  # PVAL card (id 1) evaluating the pROM; blank = nominal point

    def darea(self) -> str:
        """DAREA 8: unit forces at every `keep` DOF (two per card)."""
        pairs = [k.replace(":", ",") + ",1." for k in self.keep]
        return "".join(f"DAREA,8,{','.join(pairs[i:i + 2])}\n" for i in range(0, len(pairs), 2))


def blade_scene(size: str, work: Path) -> Scene:
    mesh = {"test": REPO / "meshes" / "blade", "full": REPO / "meshes" / "full" / "blade"}.get(size)
    if mesh is None:
        mesh = medium_mesh(work / "mesh")
    if not (mesh / "blade.bdf").exists():
        sys.exit(f"{mesh}/blade.bdf missing (make meshes-full for --size full)")
    rbe = (mesh / "blade_rbe.bdf").read_text()
    aset = next(line for line in rbe.splitlines() if line.startswith("ASET1")).split()[2:5]
    n_grids = sum(1 for line in (mesh / "blade.bdf").read_text().splitlines() if line.startswith("GRID"))
    model = (f"PARAM,ALPHA1,0.02\nPARAM,BETA1,0.0005\nINCLUDE '{REPO}/decks/blade/blade_ti_bolts.bdf'\n"
             f"INCLUDE '{mesh}/blade.bdf'\nINCLUDE '{mesh}/blade_rbe.bdf'\n")
    prom = "PMPAR,1,E,E,1,69.624E9,162.456E9\nPMPAR,2,RHO,RHO,1,2923.8,6822.2\nPMOR,1,5,15,500.,1.E-3,8\n,1\n"
    return Scene(f"blade --size {size}: {n_grids} grids", model, [f"{g}:3" for g in aset], prom)


def link_scene(size: str) -> Scene:
    if size != "test":
        sys.exit("--scene link has only --size test (meshes/robot/l2_composite.bdf)")
    plies = "PCOMP,1,,,,,,,SYM\n,2,0.3E-3,20.,,2,0.3E-3,-20.\n,2,0.3E-3,20.,,2,0.3E-3,-20.\n"
    model = f"{plies}INCLUDE '{REPO}/decks/crossmodel/l2r_common.bdf'\n"
    prom = "PMPAR,1,THETA,THETA,1,0.,45.\nPMOR,1,4,16,500.,1.E-3,5\n,1,ATTACH,KEEP\n"
    return Scene("link L2r (test mesh, 1579 grids, 6,402 free DOFs), THETA = 20 deg", model,
                 ["1000001:3", "1000002:3"], prom, "PVAL,1,THETA,20.\n")


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--scene", choices=["blade", "link"], default="blade")
    ap.add_argument("--size", choices=["test", "medium", "full"], default="test")
    ap.add_argument("--lines", type=int, default=100)
    ap.add_argument("--fmax", type=float, default=500.0)
    ap.add_argument("--modal-fmax", type=float, default=2000.0)
    ap.add_argument("--paraflex", default=str(default_binary()))
    ap.add_argument("--workdir", type=Path, default=Path(tempfile.gettempdir()))
    ap.add_argument("--keep", action="store_true")
    args = ap.parse_args()
    work = Path(tempfile.mkdtemp(prefix="frf_bench_", dir=args.workdir))
    try:
        scene = blade_scene(args.size, work) if args.scene == "blade" else link_scene(args.size)
        model, keep = scene.model, scene.keep
        df = args.fmax / args.lines
        freq = f"FREQ1,5,{df!r},{df!r},{args.lines - 1}\n"
        loads = f"RLOAD1,7,8,,,20\n{scene.darea()}TABLED1,20\n,0.,1.,1.E4,1.,ENDT\n"
        case = "FREQUENCY = 5\nDLOAD = 7\n"
        pval_case = "PVAL = 1\n" if scene.pval else ""
        decks = {
            "direct": f"SOL 108\nCEND\n{case}BEGIN BULK\n{freq}{loads}{model}ENDDATA\n",
            "modal": f"SOL 111\nCEND\n{case}METHOD = 10\nBEGIN BULK\nEIGRL,10,,{args.modal_fmax!r}\n{freq}{loads}{model}ENDDATA\n",
            "modes_only": (f"SOL 111\nCEND\n{case}METHOD = 10\nBEGIN BULK\nPARAM,RESVEC,NO\nEIGRL,10,,{args.modal_fmax!r}\n"
                           f"{freq}{loads}{model}ENDDATA\n"),
            "prom_build": f"SOL PROM\nCEND\nPROM = 1\nBEGIN BULK\n{scene.prom}{model}ENDDATA\n",
            "prom_frf": (f"SOL 111\nCEND\nROM = '{work}/prom_build.h5'\n{pval_case}FREQUENCY = 5\nBEGIN BULK\n"
                         f"{freq}{scene.pval}ENDDATA\n"),
        }
        times = {}
        for name, text in decks.items():
            deck = work / f"{name}.dat"
            deck.write_text(text)
            times[name] = run(args.paraflex, deck, work / f"{name}.h5")
            print(f"  {name}: {times[name]:.2f} s", file=sys.stderr)
        hz, ref = read(work / "direct.h5", keep)
        scale = np.abs(ref).max()
        print(f"{scene.title}, {args.lines} lines in (0, {args.fmax:g}] Hz, inputs/outputs {', '.join(keep)}")
        print(f"| method | wall time [s] | max error (of max abs H) | median per-line error |")
        print(f"|---|---|---|---|")
        for name, label in [("direct", "full direct (SOL 108)"),
                            ("modal", f"full modal (SOL 111, modes < {args.modal_fmax:g} Hz + residual vectors)"),
                            ("modes_only", "full modal, modes only (PARAM,RESVEC,NO)"),
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
