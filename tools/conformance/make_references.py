"""Write the pyNastran reference summary of every conformance deck.

For each ``decks/conformance/*.bdf`` this reads the deck with pyNastran
(``BDF().read_bdf``, which cross-references) and writes
``reference/conformance/<deck stem>.json``::

    {
      "provenance": "pyNastran 1.4.1 read_bdf + mass_properties(...) ...",
      "grids": <number of GRID cards>,
      "elements": {"CQUAD4": n, ...},   # every element card by name, incl.
                                        # CELAS1/CELAS2 and CONM2; CTETRA counts
                                        # 4- and 10-node tets together
      "rigid": {"RBE2": n, "RBE3": n},
      "dofs": 6 * grids,
      "mass": <float>,
      "cg": [x, y, z],                  # basic system
      "inertia_cg": [[Ixx, -Ixy, -Ixz], [-Ixy, Iyy, -Iyz], [-Ixz, -Iyz, Izz]]
    }

mass / cg / inertia come from
``pyNastran.bdf.mesh_utils.mass_properties.mass_properties(model)``: the
inertia is taken about the CG and pyNastran's [Ixx, Iyy, Izz, Ixy, Ixz, Iyz]
(with Ixy = sum m*x*y, i.e. the positive product of inertia) is turned into
the inertia tensor with negative products off the diagonal.  PARAM,WTMASS is
applied by pyNastran to mass and inertia (not to the CG).  The exact formulas
are in tools/conformance/PYNASTRAN_MASS.md.

Floats are written with Python's repr precision (json default), keys sorted,
so the output is byte-identical run to run.

Run from the repository root:  .venv/bin/python tools/conformance/make_references.py
"""
from __future__ import annotations

import json
import logging
import sys
import warnings
from collections import Counter
from pathlib import Path

import pyNastran
from pyNastran.bdf.bdf import BDF
from pyNastran.bdf.mesh_utils.mass_properties import mass_properties

REPO = Path(__file__).resolve().parents[2]
DECK_DIR = REPO / "decks" / "conformance"
REF_DIR = REPO / "reference" / "conformance"

PROVENANCE = (
    f"pyNastran {pyNastran.__version__} read_bdf + mass_properties(model) "
    "(pyNastran.bdf.mesh_utils.mass_properties; reference_point=origin, "
    "inertia_reference='cg'): each element's mass lumped at its "
    "center_of_mass(), CONM2 inertia added; PARAM,WTMASS multiplies mass and "
    "inertia, not cg. inertia_cg is the tensor about the CG "
    "[[Ixx,-Ixy,-Ixz],[-Ixy,Iyy,-Iyz],[-Ixz,-Iyz,Izz]] built from pyNastran's "
    "[Ixx,Iyy,Izz,Ixy,Ixz,Iyz] where Ixy=sum(m*dx*dy) (positive product of "
    "inertia, dx=x-xcg); formulas in tools/conformance/PYNASTRAN_MASS.md"
)


def read_deck(path: Path) -> BDF:
    log = logging.getLogger("pyNastran-quiet")
    log.setLevel(logging.ERROR)
    model = BDF(debug=None, log=None)
    model.log.level = "error"
    model.read_bdf(str(path), xref=True, punch=None)
    return model


def summarize(model: BDF) -> dict:
    elements = Counter(elem.type for elem in model.elements.values())
    elements.update(mass.type for mass in model.masses.values())
    rigid = Counter(elem.type for elem in model.rigid_elements.values())
    with warnings.catch_warnings():
        # pyNastran warns for every CONM2 with CID > 0 (its inertia is dropped);
        # the decks give such CONM2s no inertia, see PYNASTRAN_MASS.md
        warnings.filterwarnings("ignore", message=r"CONM2 \(eid=\d+\) inertia method")
        mass, cg, inertia = mass_properties(model)
    ixx, iyy, izz, ixy, ixz, iyz = (float(v) for v in inertia)
    grids = len(model.nodes)
    return {
        "provenance": PROVENANCE,
        "grids": grids,
        "elements": dict(sorted(elements.items())),
        "rigid": {"RBE2": rigid.get("RBE2", 0), "RBE3": rigid.get("RBE3", 0)},
        "dofs": 6 * grids,
        "mass": float(mass),
        "cg": [float(v) for v in cg],
        "inertia_cg": [[ixx, -ixy, -ixz], [-ixy, iyy, -iyz], [-ixz, -iyz, izz]],
    }


def _max_rel(a: dict, b: dict) -> float:
    scale = max(abs(a["mass"]), 1e-300)
    diffs = [abs(a["mass"] - b["mass"]) / scale]
    size = max(abs(v) for v in a["cg"]) or 1.0
    diffs += [abs(x - y) / size for x, y in zip(a["cg"], b["cg"])]
    iscale = max(abs(v) for row in a["inertia_cg"] for v in row) or 1.0
    diffs += [abs(x - y) / iscale for ra, rb in zip(a["inertia_cg"], b["inertia_cg"])
              for x, y in zip(ra, rb)]
    return max(diffs)


def main() -> int:
    REF_DIR.mkdir(parents=True, exist_ok=True)
    decks = sorted(DECK_DIR.glob("*.bdf"))
    if not decks:
        print("no decks in", DECK_DIR, file=sys.stderr)
        return 1
    refs = {}
    for deck in decks:
        ref = summarize(read_deck(deck))
        refs[deck.stem] = ref
        out = REF_DIR / f"{deck.stem}.json"
        out.write_text(json.dumps(ref, indent=2, sort_keys=False) + "\n")
        print(f"{out.relative_to(REPO)}: grids={ref['grids']} "
              f"mass={ref['mass']!r} elements={ref['elements']}")

    # the small/large/free decks of one model must describe the same model
    print("\nformat consistency (max relative difference vs *_small):")
    for stem, ref in refs.items():
        if not stem.endswith("_small"):
            continue
        base = stem[: -len("_small")]
        for kind in ("large", "free"):
            other = refs.get(f"{base}_{kind}")
            if other is None:
                continue
            same_counts = all(ref[k] == other[k] for k in ("grids", "elements", "rigid"))
            print(f"  {base:14s} {kind:5s} counts {'equal' if same_counts else 'DIFFER'}, "
                  f"mass/cg/inertia rel diff {_max_rel(ref, other):.3e}")
            if not same_counts:
                return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
