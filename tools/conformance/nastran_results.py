#!/usr/bin/env python3
"""paraflex against MSC Nastran's own results in pyNastran's model collection.

Many decks of the collection (see ``pynastran_models.py`` for how to get it) have the OP2 file
MSC Nastran wrote for them beside them (``deck.bdf`` → ``deck.op2``). For every SOL 101 / 103
deck that paraflex runs and that has one, this script runs paraflex and compares, per subcase:

- statics: the displacements of every grid in the OP2. Nastran writes them in each grid's
  displacement system (CD) and paraflex in basic, so the comparison is of the rotation-invariant
  lengths of each grid's translation and rotation vectors: max over grids of
  | |t|_paraflex − |t|_Nastran | / max |t|_Nastran (and the same for rotations);
- modes: the natural frequencies of the modes both computed, max relative difference.

OP2 results are single precision (relative round-off ~6e-8). Usage:

    .venv/bin/python tools/conformance/nastran_results.py --models /tmp/pyNastran/models \\
        [--paraflex target/release/paraflex] [-o docs/conformance-nastran.md]
"""
from __future__ import annotations

import argparse
import math
import subprocess
import tempfile
from pathlib import Path

import h5py
import numpy as np

from paraflex_tools import runner

from pynastran_models import structural_decks

STATICS, MODES = {"101", "SESTATIC"}, {"103", "SEMODES"}


def read_op2(path: Path):
    from pyNastran.op2.op2 import read_op2 as pyn_read

    return pyn_read(str(path), debug=None, log=None, build_dataframe=False, mode="msc")


def lengths(u: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    return np.linalg.norm(u[:, :3], axis=1), np.linalg.norm(u[:, 3:6], axis=1)


def relative(mine: np.ndarray, ref: np.ndarray) -> float:
    scale = np.abs(ref).max()
    return float(np.abs(mine - ref).max() / scale) if scale > 0 else float(np.abs(mine).max())


def compare_statics(out: h5py.File, op2) -> list[str]:
    ids = {int(g): i for i, g in enumerate(out["model/grid_ids"][:])}
    rows = []
    for sc, table in sorted(op2.displacements.items()):
        key = f"results/{sc}/statics/displacement"
        if key not in out:
            rows.append(f"subcase {sc}: not in paraflex's output")
            continue
        u = out[key][:]
        grids = table.node_gridtype[:, 0][table.node_gridtype[:, 1] == 1]
        ref = table.data[0][table.node_gridtype[:, 1] == 1]
        missing = [g for g in grids if g not in ids]
        if missing:
            rows.append(f"subcase {sc}: {len(missing)} grids missing")
            continue
        mine = u[[ids[g] for g in grids]]
        (tm, rm), (tr, rr) = lengths(mine), lengths(ref)
        rows.append(f"subcase {sc}: translations {relative(tm, tr):.1e}, rotations {relative(rm, rr):.1e}")
    return rows


def compare_modes(out: h5py.File, op2) -> list[str]:
    rows = []
    for title, table in op2.eigenvalues.items():
        ref = np.asarray(table.cycles, dtype=float)
        for sc in out["results"]:
            key = f"results/{sc}/modal/frequency_hz"
            if key not in out:
                continue
            mine = out[key][:]
            n = min(len(mine), len(ref))
            # rigid-body modes (near 0 Hz in both) are compared on the scale of the first elastic one
            scale = np.maximum(np.abs(ref[:n]), max(1e-3 * ref[:n].max(), 1e-12))
            err = float(np.max(np.abs(mine[:n] - ref[:n]) / scale)) if n else math.nan
            rows.append(f"subcase {sc}: {n} modes, frequencies {err:.1e} (first {ref[0]:.4g} Hz)")
        break
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--models", type=Path, required=True)
    ap.add_argument("--paraflex", default=None)
    ap.add_argument("--timeout", type=float, default=120.0)
    ap.add_argument("-o", "--output", type=Path)
    ap.add_argument("--label", default="")
    args = ap.parse_args()
    binary = runner.find_binary(args.paraflex).resolve()
    table = []
    for deck, sol in structural_decks(args.models):
        op2 = deck.with_suffix(".op2")
        if sol not in STATICS | MODES or not op2.exists():
            continue
        name = deck.relative_to(args.models).as_posix()
        with tempfile.TemporaryDirectory() as scratch:
            h5 = Path(scratch) / "out.h5"
            try:
                p = subprocess.run([str(binary), "run", str(deck), "-o", str(h5)], capture_output=True,
                                   text=True, timeout=args.timeout, cwd=deck.parent)
            except subprocess.TimeoutExpired:
                continue
            if p.returncode != 0:
                continue
            try:
                results = read_op2(op2)
            except Exception as e:  # an OP2 pyNastran cannot read is reported, not fatal
                table.append((name, sol, [f"OP2 not readable: {type(e).__name__}"]))
                continue
            with h5py.File(h5) as out:
                rows = compare_statics(out, results) if sol in STATICS else compare_modes(out, results)
        table.append((name, sol, rows or ["no result table in the OP2"]))
        print(name, rows, flush=True)
    lines = [
        "# paraflex against MSC Nastran's results",
        "",
        "Made by `tools/conformance/nastran_results.py` (its header says what is compared and how)"
        + (f"; collection: {args.label}" if args.label else "")
        + ". Every SOL 101/103 deck of the collection that paraflex runs and that has MSC Nastran's OP2"
        " beside it. Statics: max over grids of the difference of the translation (rotation) vector"
        " lengths relative to the largest; modes: max relative frequency difference. OP2 values are"
        " single precision (~6e-8).",
        "",
        "| deck | SOL | comparison |",
        "|---|---|---|",
        *[f"| `{n}` | {s} | {'; '.join(r)} |" for n, s, r in table],
        "",
    ]
    text = "\n".join(lines)
    if args.output:
        args.output.write_text(text)
    else:
        print(text)


if __name__ == "__main__":
    main()
