#!/usr/bin/env python3
"""Reference results from MSC Nastran's own OP2 files in pyNastran's model collection.

    .venv/bin/python tools/conformance/msc_reference.py --models /tmp/pyNastran/models \\
        --label "pyNastran commit 1d25a9244"

writes reference/nastran/pload1_cbar.json: the displacements MSC Nastran computed for
models/unit/pload4/pload1.bdf (a CBAR cantilever under nine PLOAD1 cases; the same model is
decks/verify/pload1_cbar.dat), read from the OP2 beside it with pyNastran.
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
    path = ROOT / "reference" / "nastran" / "pload1_cbar.json"
    path.write_text(json.dumps(out, indent=1) + "\n")
    print(f"wrote {path.relative_to(ROOT)}")


if __name__ == "__main__":
    main()
