#!/usr/bin/env python3
"""Four-bar linkage links of thesis §4.4 (Fig. 4.2–4.3): input crank (IC), coupler (C) and
output crank (OC) as flat shell strips, with a master grid at each revolute joint.

From the thesis:
- constant cross-section 10 mm × 2 mm (§4.4.1), modelled with 4-node shells (§4.4.1: "4-node
  linear shell elements"): the 10 mm width is the shell's in-plane width, the 2 mm the PSHELL
  thickness (Table 4.2: h = 2 mm);
- material (in the decks, not here): Table 4.2, E 201.99 GPa, ρ 7990 kg/m³, ν 0.34; the
  composite coupler: 8 layers of the CFRP of Table 3.6;
- the full variant's density: Table 4.1 gives the FOM sizes IC 25,338, C 88,338, OC 75,738 DOFs
  (4,223, 14,723, 12,623 grids at 6 DOFs); with the lengths below, the 0.5 mm "full" mesh has
  4,689, 15,182, 13,087 grids (+11 %, +3 %, +4 %), so the thesis meshes were about this fine.

Choices (the thesis shows the lengths only in Fig. 4.2, which is not in the text):
- joint-to-joint lengths IC 100 mm, C 350 mm, OC 300 mm: in the ratio of Table 4.1's grid counts
  (1 : 3.49 : 2.99), which at one mesh density is the ratio of the strip areas; 100 mm for the
  crank is a plausible bench-top scale (the drive oscillates IC by 0–20° at 10 Hz, §4.4.2).
  100 + 350 ≤ 300 + a ground link ≥ 150 mm satisfies Grashof's condition (IC can rotate fully);
- each end is a half-disc of radius 5 mm (the half width) around a 4 mm joint hole: the pin hole
  of a revolute joint; the ligament around the hole is 3 mm;
- the links lie in the x–y plane (the plane of the mechanism), joint axes along z; joint 1 at
  the origin, joint 2 at (L, 0, 0);
- each hole's edge is tied by an RBE2 (all six components) to a master grid at the hole centre
  (ids 1000001, 1000002), the joint of the multibody model; ASET1 123456 on both masters
  (boundary DOFs for static modes, as in §4.5 for the Robolink links).

Sizes: "test" 2.5 mm elements with 12 segments per hole (committed includes, fast tests);
"full" 0.5 mm with 32 segments per hole (Table 4.1 density, ``make meshes-full``).
Elements are quads with some triangles (gmsh frontal-Delaunay for quads + recombination).
Every shell element carries MCID = 0 (basic system), so the composite layup of the coupler
deck has its 0° direction along the link axis x in every element.
"""
from __future__ import annotations

import argparse
import math
from pathlib import Path

import gmsh

from paraflex_tools import meshing
from paraflex_tools.cards import card

PROVENANCE = "meshes/fourbar.py"
WIDTH = 0.010          # m, §4.4.1
HOLE_DIAMETER = 0.004  # m, choice
LINKS = {              # component → joint-to-joint length (m), choice (see docstring)
    "crank": 0.100,
    "coupler": 0.350,
    "output_crank": 0.300,
}
SIZES = {"test": (0.0025, 12), "full": (0.0005, 32)}  # element size (m), segments per hole
MASTER_BASE = 1000001
SURFACE, HOLE1, HOLE2 = 1, 11, 12  # physical group tags
PID = 1


def link_mesh(name: str, length: float, size: str, out: Path) -> list[Path]:
    """Mesh one link and write ``<name>.bdf`` and ``<name>_rbe.bdf``."""
    h, n_hole = SIZES[size]
    r_end, r_hole = WIDTH / 2, HOLE_DIAMETER / 2
    with meshing.gmsh_session(name):
        occ = gmsh.model.occ
        bar = occ.addRectangle(0.0, -r_end, 0.0, length, WIDTH)
        ends = [occ.addDisk(0.0, 0.0, 0.0, r_end, r_end), occ.addDisk(length, 0.0, 0.0, r_end, r_end)]
        body, _ = occ.fuse([(2, bar)], [(2, d) for d in ends])
        holes = [occ.addDisk(0.0, 0.0, 0.0, r_hole, r_hole), occ.addDisk(length, 0.0, 0.0, r_hole, r_hole)]
        plate, _ = occ.cut(body, [(2, d) for d in holes])
        occ.synchronize()
        surfaces = [tag for dim, tag in plate if dim == 2]
        if len(surfaces) != 1:
            raise RuntimeError(f"{name}: expected one surface, got {plate}")
        hole_curves = {}
        for dim, tag in gmsh.model.getBoundary(plate, oriented=False):
            xmin, ymin, _, xmax, ymax, _ = gmsh.model.getBoundingBox(dim, tag)
            if xmax - xmin < 1.01 * HOLE_DIAMETER and ymax - ymin < 1.01 * HOLE_DIAMETER:
                centre = 0.5 * (xmin + xmax)
                hole_curves.setdefault(0 if centre < length / 2 else 1, []).append(tag)
        if sorted(hole_curves) != [0, 1]:
            raise RuntimeError(f"{name}: did not find both hole edges")
        for curves in hole_curves.values():
            for c in curves:
                gmsh.model.mesh.setTransfiniteCurve(c, n_hole // len(curves) + 1)
        gmsh.model.addPhysicalGroup(2, surfaces, SURFACE)
        gmsh.model.addPhysicalGroup(1, hole_curves[0], HOLE1)
        gmsh.model.addPhysicalGroup(1, hole_curves[1], HOLE2)
        gmsh.option.setNumber("Mesh.MeshSizeMin", h)
        gmsh.option.setNumber("Mesh.MeshSizeMax", h)
        gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 0)
        gmsh.option.setNumber("Mesh.Algorithm", 8)               # frontal-Delaunay for quads
        gmsh.option.setNumber("Mesh.RecombinationAlgorithm", 0)  # simple: leaves some triangles
        gmsh.option.setNumber("Mesh.RecombineAll", 1)
        gmsh.model.mesh.generate(2)
        mesh = meshing.extract({(2, SURFACE): PID})
        spiders = [mesh.grids_of(1, HOLE1), mesh.grids_of(1, HOLE2)]

    out.mkdir(parents=True, exist_ok=True)
    mesh_path, rbe_path = out / f"{name}.bdf", out / f"{name}_rbe.bdf"
    meshing.fit_large_field(mesh)
    meshing.write_mesh_include(mesh, mesh_path, PROVENANCE)
    meshing.set_shell_mcid(mesh_path, 0)
    cards = []
    masters = []
    for k, (x, dependents) in enumerate(zip((0.0, length), spiders)):
        gid = MASTER_BASE + k
        masters.append(gid)
        cards.append(card("GRID", gid, None, x, 0.0, 0.0, form="fit"))
        cards.append(card("RBE2", gid, gid, "123456", *dependents, form="fit"))
    cards.append(card("ASET1", "123456", *masters, form="fit"))
    meshing.write_cards(rbe_path, PROVENANCE, cards,
                        f"{name}: joint masters {masters[0]} at x = 0 and {masters[1]} at x = "
                        f"{length} m, RBE2 (123456) to the hole edges, ASET1 of the masters")
    return [mesh_path, rbe_path]


def generate(out: Path, size: str) -> list[Path]:
    """Write the includes of the three links into ``out``; size is "test" or "full"."""
    if size not in SIZES:
        raise ValueError(f"size must be one of {sorted(SIZES)}, got {size!r}")
    paths = []
    for name, length in LINKS.items():
        paths += link_mesh(name, length, size, out)
    return paths


def main() -> None:
    ap = argparse.ArgumentParser(description="four-bar links (thesis §4.4) → Nastran includes")
    ap.add_argument("--size", choices=sorted(SIZES), default="test")
    ap.add_argument("--out", type=Path, help="default meshes/fourbar/ (test) or meshes/full/fourbar/ (full)")
    args = ap.parse_args()
    here = Path(__file__).resolve().parent
    out = args.out or (here / "fourbar" if args.size == "test" else here / "full" / "fourbar")
    for p in generate(out, args.size):
        print(p)


if __name__ == "__main__":
    main()
