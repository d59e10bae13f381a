"""Robolink-like manipulator links (thesis §4.5, Fig. 4.13–4.17; §3.6, Fig. 3.15; §6.3.1, Fig. 6.3).

Generates, with the gmsh OCC kernel, shell meshes (recombined 2-D meshing: mostly CQUAD4 with a
few CTRIA3, as the thesis's "3 and 4-nodes shell elements") of

* ``l1``: the first link, one folded steel sheet (U bracket): a base bolted on the M1 output
  flange and two uprights holding M2 between them;
* ``l2``: one side of the second link (L2r = L2l), a folded (joggled) steel strip from M2 to M3
  with lightening holes;
* ``l3``: one side of the third link (L3r = L3l), the same construction from M3 to M4;
* ``l2_composite``, ``l3_composite``: the simplified sides for composite manufacturing (Fig. 4.17,
  Fig. 6.3): same outline, ending sections unmodified (motor and bolt holes kept), lightening
  holes removed. Elements carry MCID = 0 so the material x axis is the projection of the basic
  x axis, which is the link's long axis (the thesis takes "the global z axis" as the fibre
  reference direction of its model, §3.6.1: the long axis of its link; ours lies along x);
* ``base_plate``: the 5 mm aluminium plate of the test bench that carries M1 (Table 4.8).

Every face in contact with a motor (the annulus between the motor hole and the motor flange
radius, bolt holes included) is tied by one RBE2 (all six components) to a master grid on the
motor axis (ids 1000001…), and the masters form the ASET1 (thesis §4.5.1: "the faces in contact
with motors in the assembly are connected to a single master node by RBEs").

Units: SI (m, kg, N, Pa), as the thesis tables.

Numbers from the thesis
-----------------------
* sheet thickness 2 mm, steel E = 201.99 GPa (L1, L2) / 194.37 GPa (L3), ρ = 7990 kg/m³,
  ν = 0.34 (Table 4.6; used in the decks);
* masses (Table 4.4): L1 0.93 kg, L2r 0.58 kg, L3r 0.36 kg; composite sides (Tables 6.1–6.2,
  half of "sum of both sides", 8 layers, 2.4 mm): L2 0.1768 kg, L3 0.1120 kg. Table 6.1/6.2
  give the isotropic sums 1.1702 kg and 0.7126 kg (0.5851 / 0.3563 kg per side), consistent
  with Table 4.4. Table 4.4 weighs the bare sheet (§4.5.2.1: "the computed density is used
  directly to model material properties of the relative FE models"), so no CONM2 for motors or
  bolts is added: the FE sheet alone carries the mass;
* composite: 8 plies × 0.3 mm, angle-ply Θ = 20° (Table 3.6, §3.6.2), fibre/matrix data of
  Table 3.6 (the ply constants are derived in the decks' comments);
* base plate: 5 mm aluminium, E = 28.8 GPa (identified, Table 4.8), ρ = 2630 kg/m³, ν = 0.33;
  mass 13.05 kg (Table 4.4, "P").

Derived from the thesis masses (not free choices)
-------------------------------------------------
* composite outline area = m / (ρ_c t) with ρ_c = 0.6·1800 + 0.4·1200 = 1560 kg/m³, t = 2.4 mm:
  L2 side 0.0472 m², L3 side 0.0299 m² → with the chosen lengths this sets the strip widths;
* steel net area = m / (7990 · 0.002): L2 0.0363 m², L3 0.0225 m² → sets the lightening holes
  (holes remove 23–25 % of the outline, in line with "holes with the purpose of reducing the
  weight", §6.3.1);
* base plate area 13.05 / (2630 · 0.005) = 0.9924 m² → a 1 m × 1 m plate with a Ø 98 mm cable
  hole under M1.

Our choices (the thesis gives the geometry only in figures)
-----------------------------------------------------------
* sides are straight tapered strips with round ends around the motors ("stadium" outline, wider
  at the heavier proximal motor), folded twice into a joggle (offset ``joggle``, 15 / 10 mm)
  between the motor sections, as the side plates of the igus robolink arm; fold radii are
  neglected. Lightening holes: a round hole near each fold and one obround slot in the middle,
  at least ``MIN_WEB`` = 8 mm of sheet between holes and folds;
* motor axis distances (L2 419 mm, L3 310 mm), end radii (L2 53 / 45 mm, L3 46 / 40 mm), motor
  holes (Ø 40 / 32 mm, Ø 32 / 28 mm), motor flange (RBE2 annulus) radii 40 / 32 mm and
  32 / 28 mm, bolt circles (6 × Ø 5.5 mm) and the holes: see the ``L2``, ``L3`` parameter sets.
  Length, end radius and the three hole sizes were fitted (Nelder-Mead on the "test" mesh,
  objective: largest relative frequency error plus penalties on the steel and composite masses
  beyond 3 %) to Table 4.5 with the Table 4.6 materials and to the masses above, then rounded.
  The modes are, in order, 1st out-of-plane bending, 1st torsion, 2nd bending, 2nd torsion,
  3rd bending, which is also the pattern of Table 4.5 (ratios 1 : 2.5 : 2.8 : 5.1 : 5.5 for L2r,
  bending ratios near a free beam's 2.76 and 5.40, torsion ratio near 2);
* achieved ("test" mesh, paraflex SOL 103, modes 7–11; the "full" mesh is within 1 %):
  L2r 0.576 kg, 37.4 / 106.0 / 110.9 / 217.8 / 224.6 Hz (−6.6, +5.7, −2.5, +7.0, +2.4 %);
  L3r 0.372 kg, 60.1 / 157.3 / 178.6 / 370.6 / 388.5 Hz (−6.8, +6.4, −6.5, +3.0, +2.0 %);
  composite sides 0.1736 kg and 0.1154 kg; L1 0.928 kg; plate 13.05 kg;
* not met: the composite L2r at Θ = 20° gives 77.3 / 179.6 / 220.8 / 410.7 / 451.7 Hz against
  Table 3.5's 87.5 / 149.0 / 206.5 / 276.5 / 373.5 Hz. Table 3.5's ratios (1 : 1.7 : 2.4 : 3.2 :
  4.3) are far below those of any flat strip of this mass; the ±20° laminate has a large D66, so
  torsion comes out stiff. The thesis's simplified composite geometry (Fig. 4.17, 6.3) is only in
  figures, and fitting it to Table 3.5 would need a different outline than the one the masses
  and the isotropic Table 4.5 fix, so it is left as is (the JSON compares the mass only);
* L1 is a U bracket (one folded sheet: base 120 × 110 mm, uprights 160 mm high with round tops,
  no lightening holes: the mass matches without); the thesis gives only its mass and Fig. 4.16a;
  the masters are the M1 axis (base annulus) and the M2 axis (both upright annuli, one RBE2);
* the base plate is free-free (``base_plate_free``) and, as a second deck, pinned along its edge
  where it rests on the bench frame (``base_plate_supported``, SPC1 21); the robot stands at the
  plate centre.

Sizes: "test" keeps each component ≤ ~1800 grids (fast debug-mode SOL 103); "full" halves the
element size (about 3.3× the grids: L2 4759, L3 4341, L1 6386).
"""
from __future__ import annotations

import argparse
import math
from dataclasses import dataclass
from pathlib import Path

import gmsh

from paraflex_tools import REPO
from paraflex_tools.cards import card
from paraflex_tools.meshing import (SceneMesh, extract, fit_large_field, gmsh_session, set_shell_mcid,
                                    write_cards, write_mesh_include)

PROVENANCE = "meshes/robot.py"
MASTER0 = 1000001          # first master grid id
RBE_EID0 = 1000001         # first RBE2 element id
SHELL = 1                  # physical group of all shell faces (PID 1 in the decks)


@dataclass(frozen=True)
class Side:
    """One side of a two-sided link: motor axes at x = 0 (proximal, A) and x = length (B)."""

    length: float          # distance between the motor axes [m]
    r_a: float             # outer radius of the round end at A [m]
    r_b: float             # outer radius of the round end at B [m]
    hole_a: float          # motor hole radius at A [m]
    hole_b: float
    flange_a: float        # radius of the motor flange face in contact (RBE2 annulus) [m]
    flange_b: float
    joggle: float          # out-of-plane offset of end B w.r.t. end A [m]
    light: tuple           # lightening holes between the folds, each (centre position 0..1
                           # from fold A to fold B, width across / local strip width, length
                           # along / fold-to-fold span): obround slots (round when length ≤ width)
    h_test: float          # element size for "test" [m]


@dataclass(frozen=True)
class Bracket:
    """L1: base (x, y) bolted on M1 at the origin, uprights at y = ±gap/2 holding M2."""

    width: float           # x extent of base and uprights [m]
    gap: float             # distance between the uprights [m]
    height: float          # M2 axis height above the base [m]
    hole_base: float
    flange_base: float
    hole_top: float
    flange_top: float
    h_test: float


L2 = Side(length=0.419, r_a=0.053, r_b=0.045, hole_a=0.020, hole_b=0.016, flange_a=0.040,
          flange_b=0.032, joggle=0.015, h_test=0.0065,
          light=((0.15, 0.58, 0.0), (0.5, 0.39, 0.46), (0.85, 0.58, 0.0)))
L3 = Side(length=0.310, r_a=0.046, r_b=0.040, hole_a=0.016, hole_b=0.014, flange_a=0.032,
          flange_b=0.028, joggle=0.010, h_test=0.0055,
          light=((0.15, 0.57, 0.0), (0.5, 0.56, 0.40), (0.85, 0.57, 0.0)))
L1 = Bracket(width=0.120, gap=0.110, height=0.160, hole_base=0.025, flange_base=0.045,
             hole_top=0.020, flange_top=0.040, h_test=0.007)
PLATE_SIDE, PLATE_HOLE, PLATE_FLANGE, PLATE_H_TEST = 1.0, 0.049, 0.090, 0.025
MIN_WEB = 0.008            # least sheet between two holes or a hole and a fold [m]
BOLT_R = 0.00275           # Ø 5.5 mm bolt holes (M5)
N_BOLTS = 6
FULL_REFINE = 2.0          # "full" element size = test size / FULL_REFINE


def _mesh_options(h: float) -> None:
    opt = gmsh.option.setNumber
    opt("Mesh.MeshSizeMax", h)
    opt("Mesh.MeshSizeMin", h / 3)
    opt("Mesh.MeshSizeFromCurvature", 16)
    opt("Mesh.MeshSizeExtendFromBoundary", 1)
    opt("Mesh.Algorithm", 8)              # frontal-Delaunay for quads
    opt("Mesh.RecombineAll", 1)
    opt("Mesh.RecombinationAlgorithm", 1)  # blossom: quads, a few triangles left where needed
    opt("Mesh.Smoothing", 5)


def _motor_face(occ, x: float, y: float, hole: float, flange: float, bolts: bool) -> list:
    """Disks to cut (motor hole, bolt holes on the mid radius) and the flange disk (for the
    annulus), all in the plane z = 0."""
    cuts = [(2, occ.addDisk(x, y, 0, hole, hole))]
    if bolts:
        rb = 0.5 * (hole + flange)
        for k in range(N_BOLTS):
            a = 2 * math.pi * (k + 0.5) / N_BOLTS
            cuts.append((2, occ.addDisk(x + rb * math.cos(a), y + rb * math.sin(a), 0,
                                        BOLT_R, BOLT_R)))
    return cuts


def _annuli(surfaces: list, centres: list[tuple[float, float, float]],
            radius: list[float]) -> list[list[int]]:
    """Tags of the surfaces whose corner points all lie within ``radius[i]`` of ``centres[i]``:
    the pieces of the motor-flange annulus (the surrounding sheet reaches farther out)."""
    groups = []
    for centre, r in zip(centres, radius):
        tags = []
        for dim, tag in surfaces:
            corners = gmsh.model.getBoundary([(dim, tag)], combined=False, oriented=False,
                                             recursive=True)
            if all(math.dist(gmsh.model.getValue(0, p, []), centre) < r + 1e-6
                   for _, p in corners):
                tags.append(tag)
        groups.append(tags)
    return groups


def _build_side(p: Side, light: bool) -> list[tuple[float, float, float]]:
    """Geometry of one side; returns the master positions (A, B). Physical groups: SHELL (all
    faces), 11 (annulus A), 12 (annulus B)."""
    occ = gmsh.model.occ
    L, ra, rb = p.length, p.r_a, p.r_b
    s = (ra - rb) / L
    c = math.sqrt(1 - s * s)
    quad = [(ra * s, ra * c), (L + rb * s, rb * c), (L + rb * s, -rb * c), (ra * s, -ra * c)]
    pts = [occ.addPoint(x, y, 0) for x, y in quad]
    lines = [occ.addLine(pts[i], pts[(i + 1) % 4]) for i in range(4)]
    body = occ.addPlaneSurface([occ.addCurveLoop(lines)])
    outline, _ = occ.fuse([(2, body)], [(2, occ.addDisk(0, 0, 0, ra, ra)),
                                        (2, occ.addDisk(L, 0, 0, rb, rb))])
    cuts = _motor_face(occ, 0, 0, p.hole_a, p.flange_a, True)
    cuts += _motor_face(occ, L, 0, p.hole_b, p.flange_b, True)
    # folds just outside the flanges, lightening holes evenly between them
    xf1, xf2 = ra, L - rb
    if light:
        span = xf2 - xf1
        extents = []
        for pos, wfrac, lfrac in p.light:
            x = xf1 + pos * span
            d = wfrac * 2 * (ra + (rb - ra) * x / L)
            a = max(lfrac * span, d)
            extents.append((x - a / 2, x + a / 2))
            if a - d < 1e-4:
                cuts.append((2, occ.addDisk(x, 0, 0, d / 2, d / 2)))
            else:
                r = d / 2
                slot, _ = occ.fuse([(2, occ.addRectangle(x - a / 2 + r, -r, 0, a - d, d))],
                                   [(2, occ.addDisk(x - a / 2 + r, 0, 0, r, r)),
                                    (2, occ.addDisk(x + a / 2 - r, 0, 0, r, r))])
                cuts += slot
        edges = [xf1] + [v for e in sorted(extents) for v in e] + [xf2]
        if any(hi - lo < MIN_WEB for lo, hi in zip(edges[::2], edges[1::2])):
            raise ValueError(f"lightening holes closer than {MIN_WEB} m to a fold or each other")
    sheet, _ = occ.cut(outline, cuts)
    big = 1.0
    tools = [(2, occ.addDisk(0, 0, 0, p.flange_a, p.flange_a)),
             (2, occ.addDisk(L, 0, 0, p.flange_b, p.flange_b)),
             (2, occ.addRectangle(-big, -big, 0, big + xf1, 2 * big)),
             (2, occ.addRectangle(xf2, -big, 0, big, 2 * big))]
    _, children = occ.fragment(sheet, tools)
    keep = sorted({dt for ch in children[:len(sheet)] for dt in ch})
    drop = sorted({dt for ch in children[len(sheet):] for dt in ch} - set(keep))
    occ.remove(drop, recursive=True)
    occ.synchronize()
    # fold: everything beyond x = xf1 turns by +alpha about the fold line, then everything beyond
    # xf2 turns back so that end B is parallel to end A, offset by the joggle
    alpha = math.asin(p.joggle / (xf2 - xf1))
    mid = [dt for dt in keep if occ.getCenterOfMass(*dt)[0] > xf1]
    end_b = [dt for dt in keep if occ.getCenterOfMass(*dt)[0] > xf2]
    occ.rotate(mid, xf1, 0, 0, 0, 1, 0, -alpha)
    f2 = (xf1 + (xf2 - xf1) * math.cos(alpha), 0, (xf2 - xf1) * math.sin(alpha))
    occ.rotate(end_b, *f2, 0, 1, 0, alpha)
    occ.removeAllDuplicates()
    occ.synchronize()
    surfaces = gmsh.model.getEntities(2)
    b = (f2[0] + (L - xf2), 0, p.joggle)
    ring_a, ring_b = _annuli(surfaces, [(0, 0, 0), b], [p.flange_a, p.flange_b])
    gmsh.model.addPhysicalGroup(2, [t for _, t in surfaces], SHELL)
    gmsh.model.addPhysicalGroup(2, ring_a, 11)
    gmsh.model.addPhysicalGroup(2, ring_b, 12)
    return [(0.0, 0.0, 0.0), b]


def _build_bracket(p: Bracket) -> list[tuple[float, float, float]]:
    occ = gmsh.model.occ
    w, g, hgt = p.width, p.gap, p.height
    base = [(2, occ.addRectangle(-w / 2, -g / 2, 0, w, g))]
    base, _ = occ.cut(base, _motor_face(occ, 0, 0, p.hole_base, p.flange_base, True))
    parts = list(base)
    flanges = [(2, occ.addDisk(0, 0, 0, p.flange_base, p.flange_base))]
    for side in (-1, 1):
        up, _ = occ.fuse([(2, occ.addRectangle(-w / 2, 0, 0, w, hgt))],
                         [(2, occ.addDisk(0, hgt, 0, w / 2, w / 2))])
        up, _ = occ.cut(up, _motor_face(occ, 0, hgt, p.hole_top, p.flange_top, True))
        fl = [(2, occ.addDisk(0, hgt, 0, p.flange_top, p.flange_top))]
        for dts in (up, fl):
            occ.rotate(dts, 0, 0, 0, 1, 0, 0, math.pi / 2)
            occ.translate(dts, 0, side * g / 2, 0)
        parts += up
        flanges += fl
    _, children = occ.fragment(parts, flanges)
    keep = sorted({dt for ch in children[:len(parts)] for dt in ch})
    drop = sorted({dt for ch in children[len(parts):] for dt in ch} - set(keep))
    occ.remove(drop, recursive=True)
    occ.removeAllDuplicates()
    occ.synchronize()
    surfaces = gmsh.model.getEntities(2)
    ring_base, ring_l, ring_r = _annuli(surfaces, [(0, 0, 0), (0, -g / 2, hgt), (0, g / 2, hgt)],
                                        [p.flange_base, p.flange_top, p.flange_top])
    gmsh.model.addPhysicalGroup(2, [t for _, t in surfaces], SHELL)
    gmsh.model.addPhysicalGroup(2, ring_base, 11)
    gmsh.model.addPhysicalGroup(2, ring_l + ring_r, 12)
    return [(0.0, 0.0, 0.0), (0.0, 0.0, hgt)]


def _build_plate() -> list[tuple[float, float, float]]:
    occ = gmsh.model.occ
    a = PLATE_SIDE
    plate = [(2, occ.addRectangle(-a / 2, -a / 2, 0, a, a))]
    plate, _ = occ.cut(plate, _motor_face(occ, 0, 0, PLATE_HOLE, PLATE_FLANGE, False))
    _, children = occ.fragment(plate, [(2, occ.addDisk(0, 0, 0, PLATE_FLANGE, PLATE_FLANGE))])
    keep = sorted({dt for ch in children[:len(plate)] for dt in ch})
    occ.remove(sorted({dt for ch in children[len(plate):] for dt in ch} - set(keep)),
               recursive=True)
    occ.synchronize()
    surfaces = gmsh.model.getEntities(2)
    (ring,) = _annuli(surfaces, [(0, 0, 0)], [PLATE_FLANGE])
    gmsh.model.addPhysicalGroup(2, [t for _, t in surfaces], SHELL)
    gmsh.model.addPhysicalGroup(2, ring, 11)
    # the plate's edge, where it rests on the bench frame (for the supported deck)
    edges = [t for _, t in gmsh.model.getBoundary(surfaces, oriented=False)
             if max(abs(v) for v in occ.getCenterOfMass(1, t)[:2]) > a / 2 - 1e-6]
    gmsh.model.addPhysicalGroup(1, edges, 21)
    return [(0.0, 0.0, 0.0)]


def _rbe_cards(mesh: SceneMesh, masters: list[tuple[float, float, float]],
               rings: list[int]) -> list[str]:
    cards = []
    for k, (xyz, ring) in enumerate(zip(masters, rings)):
        cards.append(card("GRID", MASTER0 + k, None, *(float(v) for v in xyz), form="fit"))
    for k, ring in enumerate(rings):
        cards.append(card("RBE2", RBE_EID0 + k, MASTER0 + k, 123456,
                          *mesh.grids_of(2, ring), form="fit"))
    cards.append(card("ASET1", 123456, *(MASTER0 + k for k in range(len(rings))), form="fit"))
    return cards


def _one(out: Path, name: str, build, h: float, rings: list[int], comment: str,
         mcid: int | None = None) -> list[Path]:
    with gmsh_session(name):
        masters = build()
        _mesh_options(h)
        gmsh.model.mesh.generate(2)
        mesh = extract({(2, SHELL): 1})
        fit_large_field(mesh)
        inc = out / f"{name}.bdf"
        write_mesh_include(mesh, inc, PROVENANCE)
        if mcid is not None:
            set_shell_mcid(inc, mcid)
        rbe = out / f"{name}_rbe.bdf"
        cards = _rbe_cards(mesh, masters, rings)
        if name == "base_plate":
            edge = sorted(set(mesh.grids_of(1, 21)))
            cards.append(card("SPC1", 21, 123, *edge, form="fit"))
        write_cards(rbe, PROVENANCE, cards, comment)
    return [inc, rbe]


# Element size factor of ``l2_composite_coarse`` (written with the "test" size only): the L2
# composite side at 3x the test element size, ~500 grids against 1579, small enough for the
# debug-build cross-model test of tests/crossmodel.rs (full-model direct FRF lines and
# transients); gmsh still refines around the motor and bolt holes (MeshSizeMin = h/3).
COARSE = 3.0


def generate(out: Path, size: str) -> list[Path]:
    if size not in ("test", "full"):
        raise ValueError(f"size must be 'test' or 'full', not {size!r}")
    f = 1.0 if size == "test" else 1.0 / FULL_REFINE
    out.mkdir(parents=True, exist_ok=True)
    ends = "masters: 1000001 = proximal motor axis (A), 1000002 = distal motor axis (B)"
    paths = []
    paths += _one(out, "l1", lambda: _build_bracket(L1), L1.h_test * f, [11, 12],
                  "L1 masters: 1000001 = M1 axis (base), 1000002 = M2 axis (both uprights)")
    for name, p in (("l2", L2), ("l3", L3)):
        paths += _one(out, name, lambda p=p: _build_side(p, True), p.h_test * f, [11, 12],
                      f"{name.upper()} side {ends}")
        paths += _one(out, f"{name}_composite", lambda p=p: _build_side(p, False),
                      p.h_test * f, [11, 12], f"{name.upper()} composite side {ends}", mcid=0)
    if size == "test":
        paths += _one(out, "l2_composite_coarse", lambda: _build_side(L2, False),
                      L2.h_test * COARSE, [11, 12],
                      f"L2 composite side, coarse (tests/crossmodel.rs) {ends}", mcid=0)
    paths += _one(out, "base_plate", _build_plate, PLATE_H_TEST * f, [11],
                  "base plate master: 1000001 = M1 axis; SPC1 21 = edge resting on the frame")
    return paths


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", choices=("test", "full"), default="test")
    ap.add_argument("--out", type=Path)
    a = ap.parse_args()
    out = a.out or (REPO / "meshes" / ("robot" if a.size == "test" else "full/robot"))
    for p in generate(out, a.size):
        print(p)


if __name__ == "__main__":
    main()
