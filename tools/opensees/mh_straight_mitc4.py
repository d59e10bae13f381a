#!/usr/bin/env python3
"""MacNeal-Harder straight cantilever, out-of-plane tip load, in OpenSees: two independent MITC4
shell elements (ShellMITC4, ASDShellQ4) on the meshes of the paraflex decks
decks/verify/mh_straight_{rectangular,parallelogram,trapezoidal}_cquad4.dat.

A third-party check of the formulation behind paraflex's CQUAD4 plate bending: the
parallelogram's 0.908 of the beam-theory target is the MITC4 element's own result
(docs/verification.md "Hard cases"). Writes reference/opensees/mh_straight_mitc4.json; tests/references.rs
(`macneal_harder_straight_beam`) asserts paraflex against it.

Needs OpenSeesPy, which the project venv does not carry (only this reference uses it):

    python3 -m venv /tmp/ops && /tmp/ops/bin/pip install -r tools/opensees/requirements.txt
    /tmp/ops/bin/python tools/opensees/mh_straight_mitc4.py -o reference/opensees/mh_straight_mitc4.json

Mesh and load as tools/calculix/macneal_harder.py (MH 1985 sec. 2.2): L = 6, depth 0.2 (y),
thickness 0.1, E = 1e7, nu = 0.3, six quads, grids 1-7 at y = 0 and 8-14 at y = 0.2, 1 and 8
clamped, 0.5 along z at 7 and 14; the result is the mean tip UZ (target 0.4321). Deterministic.
"""
from __future__ import annotations

import argparse
import json
from importlib.metadata import version

import openseespy.opensees as ops

TARGET = 0.4321
ELEMENTS = ("ShellMITC4", "ASDShellQ4")


def straight_xy(shape: str):
    """Bottom and top x of the 7 cross-sections (as tools/calculix/macneal_harder.py)."""
    xs = [float(i) for i in range(7)]
    if shape == "rectangular":
        return xs, xs
    if shape == "trapezoidal":
        off = [0.0, -0.1, 0.1, -0.1, 0.1, -0.1, 0.0]
        return [x + o for x, o in zip(xs, off)], [x - o for x, o in zip(xs, off)]
    if shape == "parallelogram":
        return xs, [x + 0.2 for x in xs]
    raise ValueError(shape)


def tip_deflection(shape: str, element: str, triangles: bool = False) -> float:
    """Mean tip UZ; `triangles`: each quad split along its 1-3 diagonal (as the CTRIA3 decks)."""
    ops.wipe()
    ops.model("basic", "-ndm", 3, "-ndf", 6)
    xb, xt = straight_xy(shape)
    for i in range(7):
        ops.node(1 + i, xb[i], 0.0, 0.0)
        ops.node(8 + i, xt[i], 0.2, 0.0)
    ops.section("ElasticMembranePlateSection", 1, 1.0e7, 0.3, 0.1, 0.0)
    for i in range(6):
        q = (1 + i, 2 + i, 9 + i, 8 + i)
        if triangles:
            ops.element(element, 1 + 2 * i, q[0], q[1], q[2], 1)
            ops.element(element, 2 + 2 * i, q[0], q[2], q[3], 1)
        else:
            ops.element(element, 1 + i, *q, 1)
    for g in (1, 8):
        ops.fix(g, 1, 1, 1, 1, 1, 1)
    ops.timeSeries("Constant", 1)
    ops.pattern("Plain", 1, 1)
    for g in (7, 14):
        ops.load(g, 0.0, 0.0, 0.5, 0.0, 0.0, 0.0)
    ops.system("FullGeneral")
    ops.numberer("Plain")
    ops.constraints("Plain")
    ops.integrator("LoadControl", 1.0)
    ops.algorithm("Linear")
    ops.analysis("Static")
    assert ops.analyze(1) == 0, f"{shape} {element}: analysis failed"
    return 0.5 * (ops.nodeDisp(7, 3) + ops.nodeDisp(14, 3))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("-o", "--output", required=True)
    args = ap.parse_args()
    cases = {}
    for shape in ("rectangular", "parallelogram", "trapezoidal"):
        values = {e: tip_deflection(shape, e) for e in ELEMENTS}
        constant_jacobian = shape != "trapezoidal"
        cases[f"mh_straight_{shape}_cquad4"] = {
            "label": "out-of-plane shear",
            "target": TARGET,
            **{e: round(v, 12) for e, v in values.items()},
            **{f"{e}_normalised": round(v / TARGET, 6) for e, v in values.items()},
            # a parallelogram has a constant Jacobian: every MITC4 interpolates the same tied
            # covariant shear strains and maps them alike, so implementations agree to the
            # solve's round-off; on the trapezoid the covariant-to-Cartesian map varies over the
            # element and implementations differ in where they evaluate it (ShellMITC4 and
            # ASDShellQ4 differ by 2.8e-4 here)
            "rel_tol": 1e-6 if constant_jacobian else 1e-3,
        }
    out = {
        "provenance": (f"OpenSeesPy {version('openseespy')} (tools/opensees/mh_straight_mitc4.py): elements ShellMITC4 "
                       "(Dvorkin-Bathe MITC4, OpenSees) and ASDShellQ4 (MITC4 shear, Petracca et al.), "
                       "ElasticMembranePlateSection E = 1e7, nu = 0.3, h = 0.1, linear static, mean tip UZ"),
        "check": "paraflex CQUAD4 tip UZ against ShellMITC4 within rel_tol (ASDShellQ4 reported beside it)",
        "cases": cases,
        # other plate formulations on the parallelogram, for comparison only (not asserted)
        "parallelogram_other_elements_normalised": {
            "ShellDKGQ (discrete Kirchhoff quad)": round(tip_deflection("parallelogram", "ShellDKGQ") / TARGET, 6),
            "ShellDKGT (discrete Kirchhoff triangle, 1-3 split)": round(tip_deflection("parallelogram", "ShellDKGT", True) / TARGET, 6),
            "ASDShellT3 (triangle, 1-3 split)": round(tip_deflection("parallelogram", "ASDShellT3", True) / TARGET, 6),
        },
    }
    with open(args.output, "w") as f:
        json.dump(out, f, indent=1)
        f.write("\n")
    for case, c in cases.items():
        print(case, {e: c[f"{e}_normalised"] for e in ELEMENTS})


if __name__ == "__main__":
    main()
