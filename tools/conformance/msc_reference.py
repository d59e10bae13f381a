#!/usr/bin/env python3
"""Reference results from MSC Nastran's own OP2 files in pyNastran's model collection.

    .venv/bin/python tools/conformance/msc_reference.py --models /tmp/pyNastran/models \\
        --label "pyNastran commit 1d25a9244"

writes, from the OP2 files beside the collection's decks (read with pyNastran):
- reference/nastran/pload1_cbar.json: the displacements MSC Nastran computed for
  models/unit/pload4/pload1.bdf (a CBAR cantilever under nine PLOAD1 cases; the same model is
  decks/verify/pload1_cbar.dat);
- reference/nastran/beam_modes.json: the natural frequencies Simcenter Nastran computed for
  models/beam_modes/beam_modes.dat (a thick CBAR/CBEAM cantilever with a tip CONM2; the model
  with explicit sections is decks/verify/beam_modes.dat);
- reference/nastran/pcomp_thermal_v10112.json: the displacements and ply stresses MSC Nastran
  computed for models/other/v10112.bdf (one PCOMP CQUAD4 [0/90/0] under ΔT = 1, a membrane load
  and two SUBCOMs, one with its own TEMP(LOAD); the same model is
  decks/verify/pcomp_thermal_v10112.dat).
"""
from __future__ import annotations

import argparse
import json
from pathlib import Path

from pyNastran.op2.op2 import read_op2

ROOT = Path(__file__).resolve().parents[2]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--models", type=Path, required=True)
    ap.add_argument("--label", default="")
    args = ap.parse_args()
    source = "unit/pload4/pload1.op2"
    op2 = read_op2(str(args.models / source), debug=None, log=None, build_dataframe=False, mode="msc")
    subcases = {}
    for sc, table in sorted(op2.displacements.items()):
        grids = table.node_gridtype[:, 0].tolist()
        subcases[str(sc)] = {str(g): [float(v) for v in row] for g, row in zip(grids, table.data[0])}
    out = {
        "case": "pload1_cbar",
        "deck": "decks/verify/pload1_cbar.dat",
        "description": "CBAR cantilever under concentrated and distributed PLOAD1 forces and moments",
        "provenance": f"MSC Nastran ({op2._nastran_format}) results in pyNastran's model collection, models/{source}"
        + (f" ({args.label})" if args.label else "") + "; read with pyNastran's OP2 reader",
        "units": "displacement T1 T2 T3 R1 R2 R3 per grid, basic system (every CD is 0)",
        "tolerance": "1e-6 of the subcase's largest component: the OP2 stores single precision (6e-8 relative)",
        "displacement": subcases,
    }
    write("pload1_cbar.json", out)
    source = "beam_modes/beam_modes_m2.op2"
    op2 = read_op2(str(args.models / source), debug=None, log=None, build_dataframe=False, mode="nx")
    table = next(iter(op2.eigenvalues.values()))
    write("beam_modes.json", {
        "case": "beam_modes",
        "deck": "decks/verify/beam_modes.dat",
        "description": "nine CBAR and one CBEAM (ROD section, radius 1, L = 10) clamped at one end, "
        "tip CONM2, lumped mass (Nastran's default): the first ten natural frequencies",
        "provenance": f"Simcenter Nastran 2019 ({op2._nastran_format}) results in pyNastran's model collection, "
        f"models/{source} (the f06 beside it prints the same values)"
        + (f" ({args.label})" if args.label else "") + "; read with pyNastran's OP2 reader",
        "model_note": "the collection's deck gives the sections as PBARL/PBEAML ROD; Nastran computes their "
        "shear factors itself, and K1 = K2 = 0.9 reproduces its bending frequencies to five digits, so the "
        "paraflex deck gives PBAR/PBEAM with J = pi r^4/2, I = pi r^4/4 and K1 = K2 = 0.9 explicitly",
        "tolerance": "1e-6 relative: the OP2 stores single precision (6e-8) and both solve the same discrete model",
        "frequency_hz": [float(f) for f in table.cycles],
    })
    source = "other/v10112.op2"
    op2 = read_op2(str(args.models / source), debug=None, log=None, build_dataframe=False, mode="msc")
    displacement, plies = {}, {}
    for sc, table in sorted(op2.displacements.items()):
        grids = table.node_gridtype[:, 0].tolist()
        displacement[str(sc)] = {str(g): [float(v) for v in row] for g, row in zip(grids, table.data[0])}
    for sc, table in sorted(op2.op2_results.stress.cquad4_composite_stress.items()):
        plies[str(sc)] = [[float(v) for v in row[:3]] for row in table.data[0]]
    write("pcomp_thermal_v10112.json", {
        "case": "pcomp_thermal_v10112",
        "deck": "decks/verify/pcomp_thermal_v10112.dat",
        "description": "one CQUAD4 of a [0/90/0] PCOMP (Jones, Mechanics of Composite Materials, 1975, "
        "pp. 199-201): subcase 10 a uniform temperature rise of 1 (TEMP(LOAD) of a TEMPD), subcase 20 "
        "Nx = 12 for t = 12, SUBCOM 30 = -200 x (10) + 3400 x (20) with TEMP(LOAD) = -200 for its stresses, "
        "SUBCOM 40 = 5320 x the most recent subcase (20)",
        "provenance": f"MSC Nastran ({op2._nastran_format}) results in pyNastran's model collection, models/{source}"
        + (f" ({args.label})" if args.label else "") + "; read with pyNastran's OP2 reader",
        "units": "displacement T1 T2 T3 R1 R2 R3 per grid, basic system; ply stresses [sigma1, sigma2, tau12] "
        "in the ply axes, plies 1-3 bottom to top, element 101",
        "tolerance": "1e-6 of the subcase's largest value: the OP2 stores single precision (6e-8 relative)",
        "displacement": displacement,
        "ply_stress": plies,
    })


def write(name: str, data: dict) -> None:
    path = ROOT / "reference" / "nastran" / name
    path.write_text(json.dumps(data, indent=1) + "\n")
    print(f"wrote {path.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
