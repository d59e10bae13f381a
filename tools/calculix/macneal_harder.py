"""MacNeal-Harder standard problems: paraflex decks, CalculiX runs of the same meshes, references.

MacNeal, R. H. and Harder, R. L., "A proposed standard set of problems to test finite element
accuracy", Finite Elements in Analysis and Design 1 (1985) 3-20 (below: MH 1985).

For every (problem, element) pair this writes

* ``decks/verify/hard/<case>.dat``          the SOL 101 deck, one SUBCASE per load,
* ``tools/calculix/work/<case>.inp``        the same mesh in CalculiX (one *STEP per load),
* ``reference/calculix/hard/<case>.json``   per load: the MH 1985 target value, CalculiX's
                                            value, the linear functional of the displacements
                                            both codes are measured with, and the stated bound.

Run from the repository root through make_references.py:

    .venv/bin/python tools/calculix/make_references.py --hard

Elements: CQUAD4 <-> S4 (ccx expands it into a C3D8I brick of the shell thickness),
CTRIA3 <-> S3 (expanded into a C3D6 wedge), CHEXA <-> C3D8I.

Bounds (decided from the element formulations and published results, never from paraflex's
number; published = MH 1985 as reproduced in Altair OptiStruct verification OS-V 0720/0700):

* ``accurate``: |normalised - 1| <= tol, where the element class is expected to be accurate.
  2 % for extension (patch test) and the thick twisted CQUAD4 (published QUAD4 0.988/0.992);
  5 % for plate bending of rectangles (published QUAD4/TRI3 0.973-0.981), in-plane bending of
  rectangles (published QUAD4 0.992) and the thin twisted CQUAD4 (MITC4 has no shear locking).
* ``same_element``: |paraflex / CalculiX - 1| <= 3 % where both codes use the same
  interpolation on the same mesh (CHEXA = C3D8I): they must agree whatever the accuracy against
  the target.
* ``same_element_cst``: the in-plane loads of the CTRIA3 strips, whose membrane is the
  plane-stress constant-strain triangle (plus a weak drilling tie): |paraflex / CST - 1| <= 0.1 %
  against the plane-stress CST solution of the same mesh computed here (``cst_plane_stress``,
  numpy). CalculiX's S3 is not that element: ccx expands it into a 3-D C3D6 wedge one element
  thick, 3.1 % stiffer than the CST on the locked parallelogram; its value is reported only.

Besides its bound, every out-of-plane load of the straight CQUAD4/CTRIA3 strips carries
``mitc_plate``: the same mesh as a flat Reissner-Mindlin plate with the published MITC4 (Dvorkin &
Bathe 1984) or MITC3 (Lee & Bathe 2004) assumed transverse shear, computed here with numpy from the
papers' tying rules. paraflex's shells must equal it to ``mitc_plate_rel_tol`` (flat: bending and
shear do not couple to the membrane): this separates an implementation error from a property of
the element class on a distorted mesh.
* ``weak``: a case 4-node/3-node elements are known to be poor at (in-plane bending of
  trapezoids/parallelograms, plate bending of trapezoids/parallelograms with one element across,
  twist with one element across, the CTRIA3 twisted beam).
  Asserted: normalised >= 0.25 x max(CalculiX, published) and <= 1.05 x max(1, CalculiX,
  published). The factor 4 is the spread of sound formulations on these meshes (one vendor's
  QUAD4 0.173 vs HEX8 0.047 on the trapezoid, OS-V 0720); a defect (locking, a missing
  drilling or incompatible mode, a wrong warping correction) is off by 10-1000x.
"""
from __future__ import annotations

import json
import math
import re
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from paraflex_tools.cards import card
from paraflex_tools.mitc_plate import mitc_plate, solve_clamped

ROOT = Path(__file__).resolve().parents[2]
DECKS = ROOT / "decks" / "verify" / "hard"
REFS = ROOT / "reference" / "calculix" / "hard"
MH1985 = ('MacNeal, R. H. and Harder, R. L., "A proposed standard set of problems to test finite '
          'element accuracy", Finite Elements in Analysis and Design 1 (1985) 3-20')
ALTAIR = ("target values also reproduced in Altair OptiStruct verification problems OS-V 0720 "
          "(straight cantilever) and OS-V 0700 (twisted beam), help.altair.com")

ACCURATE_TOL = 0.02
BENDING_TOL = 0.05
SAME_TOL = 0.03
# paraflex's CTRIA3 membrane against the plane-stress CST: its weak drilling tie (1e-3 A66) makes
# the in-plane tip displacement 2.9e-5 / 1.7e-4 / 1.2e-4 smaller than the CST's on the
# parallelogram / rectangle / trapezoid (measured; with the tie at 1e-9 A66 the two agree to
# 5e-8); 0.1 % is the largest with a factor 6 to spare, and far below any formulation error (a
# drilling tie of 1e-1 A66 already misses it on all three meshes).
CST_TOL = 1e-3
# paraflex's flat MITC4/MITC3 against the independent plate of the same formulation: measured
# agreement 2.4e-10 or better (the round-off of two solves and of the JSON's 12 digits); 1e-6
# leaves that ample room and catches any formulation difference: MITC3 without its c term moves
# the parallelogram from 0.568 to 0.902 and the trapezoid from 0.931 to 0.961, shear taken at the
# integration points instead of tied locks every mesh (0.01-0.03).
MITC_TOL = 1e-6
WEAK_RATIO = 0.25
SOFT_CAP = 1.05


def r12(x: float) -> float:
    """Coordinates rounded once so that both decks carry the same numbers."""
    v = round(float(x), 12)
    return 0.0 if v == 0.0 else v


@dataclass
class Load:
    label: str
    forces: list  # (grid, dof 1..3, value)
    measure: list  # (grid, dof 1..3, weight): result = sum weight * u
    target: float
    target_note: str
    bound: dict


@dataclass
class Case:
    name: str
    problem: str
    element: str  # CQUAD4 / CTRIA3 / CHEXA
    shape: str
    nodes: dict  # id -> (x, y, z)
    elems: list  # (eid, conn)
    clamp: list
    E: float
    nu: float
    t: float | None
    loads: list = field(default_factory=list)
    mesh_note: str = ""
    maxratio: float | None = None


def split_tria(quads):
    """Each quad (1, 2, 3, 4) into (1, 2, 3) and (1, 3, 4)."""
    out = []
    for eid, (a, b, c_, d) in quads:
        out.append((2 * eid - 1, (a, b, c_)))
        out.append((2 * eid, (a, c_, d)))
    return out


# --------------------------------------------------------------------------------------------
# straight cantilever (MH 1985 sec. 2.2, fig. 2): L = 6, depth (in-plane) 0.2, thickness 0.1,
# E = 1e7, nu = 0.3, six elements; loads unit forces at the tip.
# --------------------------------------------------------------------------------------------

STRAIGHT_TARGETS = {
    "extension": (3.0e-5, "UX, P L/(E A)"),
    "in-plane shear": (0.1081, "UY, beam theory P L^3/(3 E I) + shear"),
    "out-of-plane shear": (0.4321, "UZ, beam theory P L^3/(3 E I) + shear"),
    "twist": (0.03208, "rotation about x, (w(y=0.2) - w(y=0)) / 0.2 at the tip"),
}


def straight_xy(shape: str):
    """Bottom (y = 0) and top (y = 0.2) x stations of the 7 cross-sections."""
    xs = [float(i) for i in range(7)]
    if shape == "rectangular":
        return xs, xs
    if shape == "trapezoidal":  # interior sections inclined +-45 deg, alternating; ends square
        off = [0.0, -0.1, 0.1, -0.1, 0.1, -0.1, 0.0]
        return [x + o for x, o in zip(xs, off)], [x - o for x, o in zip(xs, off)]
    if shape == "parallelogram":  # every section inclined 45 deg (also the ends)
        return xs, [x + 0.2 for x in xs]
    raise ValueError(shape)


def straight_case(shape: str, element: str) -> Case:
    xb, xt = straight_xy(shape)
    E, nu, depth, thick = 1.0e7, 0.3, 0.2, 0.1
    nodes, elems = {}, []
    if element in ("CQUAD4", "CTRIA3"):
        for i in range(7):
            nodes[1 + i] = (r12(xb[i]), 0.0, 0.0)
            nodes[8 + i] = (r12(xt[i]), depth, 0.0)
        quads = [(1 + i, (1 + i, 2 + i, 9 + i, 8 + i)) for i in range(6)]
        elems = quads if element == "CQUAD4" else split_tria(quads)
        tip_b, tip_t = [7], [14]
        clamp = [1, 8]
    else:
        for k, z in enumerate((0.0, thick)):
            for i in range(7):
                nodes[1 + i + 14 * k] = (r12(xb[i]), 0.0, z)
                nodes[8 + i + 14 * k] = (r12(xt[i]), depth, z)
        elems = [(1 + i, (1 + i, 2 + i, 9 + i, 8 + i, 15 + i, 16 + i, 23 + i, 22 + i)) for i in range(6)]
        tip_b, tip_t = [7, 21], [14, 28]
        clamp = [1, 8, 15, 22]
    tip = tip_b + tip_t
    n = len(tip)
    loads = []
    for label, dof in (("extension", 1), ("in-plane shear", 2), ("out-of-plane shear", 3)):
        forces = [(g, dof, 1.0 / n) for g in tip]
        measure = [(g, dof, 1.0 / n) for g in tip]
        loads.append((label, forces, measure))
    if shape != "parallelogram":
        # unit torque as a couple of z forces across the depth; with skewed ends the couple
        # would also bend the beam (the two tip grids have different x), so no twist case there
        f = 1.0 / depth / len(tip_t)
        forces = [(g, 3, f) for g in tip_t] + [(g, 3, -f) for g in tip_b]
        measure = [(g, 3, 1.0 / depth / len(tip_t)) for g in tip_t] + [(g, 3, -1.0 / depth / len(tip_b)) for g in tip_b]
        loads.append(("twist", forces, measure))
    c = Case(f"mh_straight_{shape}_{element.lower()}", "straight cantilever", element, shape, nodes, elems, clamp,
             E, nu, thick if element != "CHEXA" else None,
             mesh_note=(f"6 elements, length 6, in-plane depth 0.2 (y), thickness 0.1 (z); {shape} shape: "
                        f"bottom x = {xb}, top x = {xt}"
                        + ("; CTRIA3: each quad split along its 1-3 diagonal" if element == "CTRIA3" else "")))
    for label, forces, measure in loads:
        target, note = STRAIGHT_TARGETS[label]
        c.loads.append(Load(label, forces, measure, target, note, straight_bound(shape, element, label)))
    return c


# Published normalised results of mature elements on these meshes (MH 1985 as reproduced in Altair
# OptiStruct verification OS-V 0720 / OS-V 0700): element class -> shape -> load -> value.
PUBLISHED = {
    "CQUAD4": {"rectangular": (1.000, 0.992, 0.981, 0.941), "parallelogram": (1.000, 0.712, 0.981, 0.905),
               "trapezoidal": (1.000, 0.173, 0.964, 0.869)},
    "CTRIA3": {"rectangular": (1.000, 0.032, 0.973, 1.072), "parallelogram": (1.000, 0.012, 0.955, 0.931),
               "trapezoidal": (1.000, 0.019, 0.965, 1.175)},
    "CHEXA": {"rectangular": (0.988, 0.978, 0.973, 0.892), "parallelogram": (1.012, 0.624, 0.529, 0.820),
              "trapezoidal": (1.010, 0.047, 0.030, 0.563)},
}
PUBLISHED_TWISTED = {"CQUAD4": {2: 0.988, 3: 0.992}, "CTRIA3": {2: 0.839, 3: 0.984}, "CHEXA": {2: 0.986, 3: 1.005}}
LOADS = ("extension", "in-plane shear", "out-of-plane shear", "twist")


def straight_bound(shape: str, element: str, label: str) -> dict:
    pub = PUBLISHED[element][shape][LOADS.index(label)]
    src = f"published {element[1:] if element != 'CHEXA' else 'HEX8'} {pub} (OS-V 0720, {shape})"
    if element == "CHEXA":
        return same_element(src)
    if label == "extension":
        return accurate(ACCURATE_TOL, "constant axial strain is represented exactly by every element on any shape "
                        f"(patch test); 2 % covers the clamp's Poisson constraint; {src}")
    if element == "CTRIA3" and label == "in-plane shear":
        return same_element_cst(src)
    if label == "out-of-plane shear" and shape == "rectangular":
        return accurate(BENDING_TOL, f"plate bending, tip shear on six elements: {src}; published 4-node/3-node "
                        "plate results on rectangles are 0.973-0.981; 5 %")
    if label == "out-of-plane shear":
        return weak(pub, f"plate bending of 45-degree {shape}s with one element across the depth: sound plate "
                    "formulations spread 0.76-0.98 on the parallelogram (reference/opensees: MITC4 0.908 in both "
                    "OpenSees ShellMITC4 and ASDShellQ4, discrete-Kirchhoff ShellDKGQ 0.971 and ShellDKGT 0.910, "
                    "ASDShellT3 0.764; CalculiX S4 0.836); CQUAD4/CTRIA3 are the MITC4/MITC3 the element brief "
                    "prescribes, so their own result is asserted by mitc_plate (the independent MITC plate of "
                    "this mesh, to mitc_plate_rel_tol) and, for CQUAD4, by OpenSees's ShellMITC4; "
                    f"{src}")
    if label == "in-plane shear" and shape == "rectangular":
        return accurate(BENDING_TOL, f"in-plane bending of rectangles: {src}, CalculiX C3D8I 0.992; 5 %")
    return weak(pub, "in-plane bending of 45-degree trapezoids/parallelograms (the known weakness of bilinear "
                "membranes) or twist of a 0.2 x 0.1 section with one element across" + f"; {src}")


def accurate(tol: float, why: str) -> dict:
    return {"kind": "accurate", "rel_tol": tol, "why": why}


def same_element(why: str) -> dict:
    return {"kind": "same_element", "rel_tol_to_calculix": SAME_TOL,
            "why": ("paraflex's element has the same interpolation as CalculiX's on this mesh (CHEXA and C3D8I: "
                    "trilinear with Wilson-Taylor incompatible modes), so the two must agree whatever the accuracy "
                    f"against the target; {SAME_TOL:.0%} covers the two codes' variants of the incompatible modes "
                    "on distorted bricks; " + why)}


def same_element_cst(why: str) -> dict:
    return {"kind": "same_element_cst", "rel_tol_to_cst": CST_TOL,
            "why": ("the CTRIA3 membrane is the plane-stress constant-strain triangle (with a weak drilling tie, "
                    "1e-3 A66), so paraflex must reproduce the plane-stress CST solution of this mesh "
                    "(cst_plane_stress, computed by tools/calculix/macneal_harder.py with numpy) whatever the "
                    f"accuracy against the target; {CST_TOL:.1%} covers the drilling tie (at most 1.7e-4 measured); "
                    "CalculiX's S3 is expanded into a 3-D C3D6 wedge, a different element: reported only; " + why)}


def cst_plane_stress(c: Case, forces: list) -> dict:
    """In-plane displacements (u, v, 0) per grid of the plane-stress constant-strain-triangle
    model of the flat CTRIA3 mesh `c` (z = 0) under the in-plane `forces`, clamped grids fixed:
    K = sum t A B^T D B with B the CST strain-displacement matrix, D plane stress."""
    ids = sorted(c.nodes)
    index = {g: i for i, g in enumerate(ids)}
    k = np.zeros((2 * len(ids), 2 * len(ids)))
    d = c.E / (1 - c.nu ** 2) * np.array([[1, c.nu, 0], [c.nu, 1, 0], [0, 0, (1 - c.nu) / 2]])
    for _, conn in c.elems:
        (x1, y1), (x2, y2), (x3, y3) = (c.nodes[g][:2] for g in conn)
        two_area = (x2 - x1) * (y3 - y1) - (x3 - x1) * (y2 - y1)
        dndx = np.array([y2 - y3, y3 - y1, y1 - y2]) / two_area
        dndy = np.array([x3 - x2, x1 - x3, x2 - x1]) / two_area
        b = np.zeros((3, 6))
        b[0, 0::2], b[1, 1::2], b[2, 0::2], b[2, 1::2] = dndx, dndy, dndy, dndx
        dofs = [2 * index[g] + j for g in conn for j in range(2)]
        k[np.ix_(dofs, dofs)] += c.t * 0.5 * abs(two_area) * b.T @ d @ b
    f = np.zeros(2 * len(ids))
    for g, dof, value in forces:
        assert dof in (1, 2), "in-plane loads only"
        f[2 * index[g] + dof - 1] += value
    u = solve_clamped(k, f, [index[g] for g in c.clamp], 2)
    return {g: (u[2 * index[g]], u[2 * index[g] + 1], 0.0) for g in ids}


def weak(published: float, why: str) -> dict:
    return {"kind": "weak", "published_normalised": published, "min_ratio": WEAK_RATIO, "soft_cap": SOFT_CAP,
            "why": why + (f"; bound: normalised >= {WEAK_RATIO} x max(CalculiX, published) (factor 4 = spread of "
                          f"sound formulations, module doc) and <= {SOFT_CAP} x max(1, CalculiX, published)")}


# --------------------------------------------------------------------------------------------
# twisted beam (MH 1985 sec. 2.4, fig. 4): L = 12, width 1.1, 90 deg twist root to tip,
# E = 29e6, nu = 0.22, 12 x 2 shells / 12 x 2 x 1 bricks; t = 0.32 (P = 1) and t = 0.0032
# (P = 1e-6).
# --------------------------------------------------------------------------------------------

TWISTED_TARGETS = {
    # (t, load direction at the tip grid) -> value; MH 1985 table 5
    (0.32, 3): 5.424e-3,
    (0.32, 2): 1.754e-3,
    (0.0032, 3): 5.256e-3,
    (0.0032, 2): 1.294e-3,
}


def twisted_beam_theory(t: float, dof: int, P: float) -> float:
    """Independent check of the MH 1985 targets: Euler-Bernoulli tip deflection of the
    pretwisted beam, P * int_0^L (L-x)^2 [c^2/(E I_weak) + s^2/(E I_strong)] dx with the section
    turned by theta = (pi/2) x/L (c, s = cos, sin theta for a load along z; swapped along y),
    Simpson's rule on 2000 intervals."""
    L, w, E = 12.0, 1.1, 29.0e6
    i_weak, i_strong = w * t ** 3 / 12, t * w ** 3 / 12
    n = 2000

    def f(x):
        c2 = math.cos(0.5 * math.pi * x / L) ** 2
        if dof == 2:
            c2 = 1.0 - c2
        return (L - x) ** 2 * (c2 / (E * i_weak) + (1.0 - c2) / (E * i_strong))
    h = L / n
    return P * h / 3 * sum((1 if k in (0, n) else 4 if k % 2 else 2) * f(k * h) for k in range(n + 1))


def twisted_case(t: float, element: str) -> Case:
    L, w, E, nu = 12.0, 1.1, 29.0e6, 0.22
    P = 1.0 if t == 0.32 else 1.0e-6
    nx, ny = 12, 2
    nodes = {}

    def station(i, j, zeta):
        x = L * i / nx
        th = 0.5 * math.pi * x / L
        s = -0.5 * w + w * j / ny
        return (r12(x), r12(s * math.cos(th) - zeta * math.sin(th)), r12(s * math.sin(th) + zeta * math.cos(th)))

    def nid(i, j, k=0):
        return 1 + i + (nx + 1) * j + (nx + 1) * (ny + 1) * k

    layers = [0.0] if element != "CHEXA" else [-0.5 * t, 0.5 * t]
    for k, zeta in enumerate(layers):
        for j in range(ny + 1):
            for i in range(nx + 1):
                nodes[nid(i, j, k)] = station(i, j, zeta)
    quads = [(1 + i + nx * j, (nid(i, j), nid(i + 1, j), nid(i + 1, j + 1), nid(i, j + 1))) for j in range(ny) for i in range(nx)]
    if element == "CQUAD4":
        elems = quads
    elif element == "CTRIA3":
        elems = split_tria(quads)
    else:
        elems = [(1 + i + nx * j, (nid(i, j), nid(i + 1, j), nid(i + 1, j + 1), nid(i, j + 1),
                                   nid(i, j, 1), nid(i + 1, j, 1), nid(i + 1, j + 1, 1), nid(i, j + 1, 1)))
                 for j in range(ny) for i in range(nx)]
    # consistent nodal forces of a uniform traction on the bilinear tip edge/face
    tipw = {}
    for k in range(len(layers)):
        for j in range(ny + 1):
            tipw[nid(nx, j, k)] = (0.5 if j in (0, ny) else 1.0) / ny / len(layers)
    clamp = [nid(0, j, k) for k in range(len(layers)) for j in range(ny + 1)]
    tag = "thick" if t == 0.32 else "thin"
    c = Case(maxratio=None if t == 0.32 else 1.0e10, name=f"mh_twisted_{tag}_{element.lower()}", problem="twisted beam", element=element,
             shape=f"warped (90 deg twist, t = {t})", nodes=nodes, elems=elems, clamp=clamp, E=E, nu=nu,
             t=t if element != "CHEXA" else None,
             mesh_note=(f"12 x 2{' x 1' if element == 'CHEXA' else ''} elements, length 12, width 1.1 twisted 90 deg "
                        f"linearly from the root (width along y) to the tip (width along z), thickness {t}; each "
                        f"shell element is warped by 7.5 deg of twist over its length"
                        + ("; CTRIA3: each quad split along its 1-3 diagonal" if element == "CTRIA3" else "")))
    for dof, lname in ((3, "load z (normal to the root plane)"), (2, "load y (along the root width)")):
        forces = [(g, dof, P * wt) for g, wt in tipw.items()]
        measure = [(g, dof, 1.0 / len(tipw)) for g in tipw]  # mean of the tip grids
        c.loads.append(Load(lname, forces, measure, TWISTED_TARGETS[(t, dof)],
                            f"U{'YZ'[dof - 2]} at the tip, P = {P:g}; MH 1985 (in-plane/out-of-plane referring to "
                            f"the tip plane); independent check, Euler-Bernoulli beam with the rotating section: "
                            f"{twisted_beam_theory(t, dof, P):.4e}", twisted_bound(t, element, dof)))
    return c


def twisted_bound(t: float, element: str, dof: int) -> dict:
    pub = PUBLISHED_TWISTED[element][dof]
    src = f"published {element[1:] if element != 'CHEXA' else 'HEX8'} {pub} on the thick beam (OS-V 0700)"
    if element == "CHEXA":
        return same_element(src)
    if element == "CQUAD4":
        if t == 0.32:
            return accurate(ACCURATE_TOL, f"warped MITC4 (7.5 deg twist per element): {src}; 2 %")
        return accurate(BENDING_TOL, "thin (t/L = 2.7e-4) warped MITC4: Bathe-Dvorkin shear interpolation is free "
                        f"of shear locking, so the thick-beam accuracy should carry over ({src}); 5 %")
    return weak(pub, "MITC3 + constant-strain membrane, 12 x 2 x 2 triangles"
                + ("" if t == 0.32 else "; thin: MITC3 is free of shear locking (Lee-Bathe 2004), so the "
                   "thick-beam published value is the class reference") + f"; {src}")


# --------------------------------------------------------------------------------------------
# writers
# --------------------------------------------------------------------------------------------


def nastran(c: Case) -> str:
    out = [f"$ MacNeal-Harder 1985 {c.problem}, {c.element}, {c.shape}",
           "$ generated by tools/calculix/macneal_harder.py (via make_references.py --hard) - do not edit",
           f"$ reference: reference/calculix/hard/{c.name}.json (MH 1985 target + CalculiX on this mesh)",
           f"$ mesh: {c.mesh_note}",
           "SOL 101", "CEND", f"TITLE = {c.name}", "SPC = 1"]
    for k, ld in enumerate(c.loads, 1):
        out += [f"$ subcase {k}: {ld.label}", f"SUBCASE {k}", f"  LOAD = {10 + k}"]
    out.append("BEGIN BULK")
    if c.maxratio is not None:
        out += ["$ thin shell: membrane/bending stiffness contrast (h/t)^2 ~ 3e4 per element puts the Cholesky",
                "$ diagonal/pivot ratio above Nastran's default MAXRATIO 1e7 (1.3e7 measured) without any",
                "$ singularity; a true mechanism gives ~1/eps = 1e15, so 1e10 still catches one",
                card("PARAM", "MAXRATIO", c.maxratio).rstrip("\n")]
    s = "".join(card("GRID", nid, None, *xyz) for nid, xyz in sorted(c.nodes.items()))
    for eid, conn in c.elems:
        s += card(c.element, eid, 1, *conn)
    if c.element == "CHEXA":
        s += card("PSOLID", 1, 1)
    else:
        s += card("PSHELL", 1, 1, c.t, 1, None, 1)
    s += card("MAT1", 1, c.E, None, c.nu, 1.0)
    comp = "123" if c.element == "CHEXA" else "123456"
    for k in range(0, len(c.clamp), 6):
        s += card("SPC1", 1, comp, *c.clamp[k:k + 6])
    for k, ld in enumerate(c.loads, 1):
        for g, dof, v in ld.forces:
            n = [0.0, 0.0, 0.0]
            n[dof - 1] = 1.0
            s += card("FORCE", 10 + k, g, 0, float(v), *n)
    return "\n".join(out) + "\n" + s + "ENDDATA\n"


def calculix(c: Case) -> str:
    et = {"CQUAD4": "S4", "CTRIA3": "S3", "CHEXA": "C3D8I"}[c.element]
    out = ["** " + c.name + " (tools/calculix/macneal_harder.py)", "*NODE, NSET=NALL"]
    out += [f"{nid}, {x!r}, {y!r}, {z!r}" for nid, (x, y, z) in sorted(c.nodes.items())]
    out.append(f"*ELEMENT, TYPE={et}, ELSET=EALL")
    out += [", ".join(str(v) for v in (eid, *conn)) for eid, conn in c.elems]
    out += ["*MATERIAL, NAME=M", "*ELASTIC", f"{c.E!r}, {c.nu!r}"]
    if c.element == "CHEXA":
        out.append("*SOLID SECTION, ELSET=EALL, MATERIAL=M")
    else:
        out += ["*SHELL SECTION, ELSET=EALL, MATERIAL=M", repr(c.t)]
    meas = sorted({g for ld in c.loads for g, _, _ in ld.measure})
    out += ["*NSET, NSET=NMEAS"] + [", ".join(str(g) for g in meas[i:i + 16]) for i in range(0, len(meas), 16)]
    out += ["*BOUNDARY"] + [f"{g}, 1, {3 if c.element == 'CHEXA' else 6}" for g in c.clamp]
    for ld in c.loads:
        out += ["*STEP", "*STATIC", "*CLOAD, OP=NEW"]
        out += [f"{g}, {dof}, {v!r}" for g, dof, v in ld.forces]
        out += ["*NODE PRINT, NSET=NMEAS", "U", "*END STEP"]
    return "\n".join(out) + "\n"


def parse_node_print(dat: Path, nsteps: int) -> list[dict]:
    """The U blocks of *NODE PRINT, one per step: {node: (ux, uy, uz)}."""
    blocks, cur = [], None
    for line in dat.read_text().splitlines():
        if re.match(r"\s*displacements \(vx,vy,vz\)", line):
            cur = {}
            blocks.append(cur)
            continue
        m = re.match(r"\s*(\d+)\s+(\S+)\s+(\S+)\s+(\S+)\s*$", line)
        if cur is not None and m:
            cur[int(m.group(1))] = tuple(float(m.group(k)) for k in (2, 3, 4))
    if len(blocks) != nsteps:
        raise RuntimeError(f"{dat}: {len(blocks)} displacement blocks, expected {nsteps}")
    return blocks


def build_cases() -> list[Case]:
    cases = [straight_case(s, e) for s in ("rectangular", "trapezoidal", "parallelogram") for e in ("CQUAD4", "CTRIA3", "CHEXA")]
    # thin CHEXA (one brick of 1 x 0.55 x 0.0032, aspect 340) is left out: paraflex refuses the
    # factorization (pivot ratio 1.6e7 > 1e7, Nastran's MAXRATIO) and CalculiX's C3D8I locks (0.02)
    cases += [twisted_case(t, e) for t in (0.32, 0.0032) for e in ("CQUAD4", "CTRIA3", "CHEXA") if (t, e) != (0.0032, "CHEXA")]
    return cases


def run_all(run_ccx, work: Path, command: str, version: str) -> list[str]:
    """Write every deck, .inp and reference; `run_ccx(job)` runs ccx in `work`."""
    DECKS.mkdir(parents=True, exist_ok=True)
    REFS.mkdir(parents=True, exist_ok=True)
    work.mkdir(parents=True, exist_ok=True)
    report = []
    for c in build_cases():
        (DECKS / f"{c.name}.dat").write_text(nastran(c))
        (work / f"{c.name}.inp").write_text(calculix(c))
        run_ccx(c.name)
        blocks = parse_node_print(work / f"{c.name}.dat", len(c.loads))
        loads = []
        for k, (ld, u) in enumerate(zip(c.loads, blocks), 1):
            val = sum(wt * u[g][d - 1] for g, d, wt in ld.measure)
            loads.append({
                "subcase": k,
                "label": ld.label,
                "target": ld.target,
                "target_source": f"{MH1985}; {ld.target_note}; {ALTAIR}",
                "calculix": float(f"{val:.10g}"),
                "calculix_normalised": float(f"{val / ld.target:.6g}"),
                "measure": [[g, d, wt] for g, d, wt in ld.measure],
                "measure_note": "result = sum weight * u(grid, dof) over the listed grids (translations, basic system)",
                "bound": ld.bound,
            })
            if ld.bound["kind"] == "same_element_cst":
                cst = cst_plane_stress(c, ld.forces)
                cst_val = sum(wt * cst[g][d - 1] for g, d, wt in ld.measure)
                loads[-1]["cst_plane_stress"] = float(f"{cst_val:.10g}")
                loads[-1]["cst_normalised"] = float(f"{cst_val / ld.target:.6g}")
            if c.problem == "straight cantilever" and c.element != "CHEXA" and ld.label == "out-of-plane shear":
                plate = mitc_plate(c, ld.forces)
                plate_val = sum(wt * plate[g][d - 1] for g, d, wt in ld.measure)
                loads[-1]["mitc_plate"] = float(f"{plate_val:.12g}")
                loads[-1]["mitc_plate_normalised"] = float(f"{plate_val / ld.target:.6g}")
                loads[-1]["mitc_plate_rel_tol"] = MITC_TOL
                loads[-1]["mitc_plate_note"] = ("the same mesh as a flat Reissner-Mindlin plate with the published "
                                                f"{'MITC4' if c.element == 'CQUAD4' else 'MITC3'} shear, numpy "
                                                "(mitc_plate in tools/calculix/macneal_harder.py): paraflex must equal "
                                                "it whatever the accuracy against the target")
            report.append(f"{c.name:34s} {ld.label:36s} ccx {val / ld.target:8.4f}")
        ref = {
            "case": c.name,
            "deck": f"decks/verify/hard/{c.name}.dat",
            "problem": f"MacNeal-Harder {c.problem}",
            "element": c.element,
            "shape": c.shape,
            "mesh": c.mesh_note,
            "material": {"E": c.E, "nu": c.nu, "thickness": c.t},
            "provenance": (f"target: {MH1985}. CalculiX {version} on the same mesh, element "
                           f"{ {'CQUAD4': 'S4 (expanded to C3D8I)', 'CTRIA3': 'S3 (expanded to C3D6)', 'CHEXA': 'C3D8I'}[c.element] }; "
                           f"command: {command.format(job=c.name)}; input tools/calculix/work/{c.name}.inp written by "
                           f"tools/calculix/macneal_harder.py; values from the *NODE PRINT U blocks of the .dat"),
            "loads": loads,
        }
        (REFS / f"{c.name}.json").write_text(json.dumps(ref, indent=1) + "\n")
    return report
