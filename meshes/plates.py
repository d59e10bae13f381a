#!/usr/bin/env python3
"""Plate and beam family for verification of the gmsh → meshio → deck path:
the same structures as closed-form solutions, meshed with gmsh and converted with meshio.

Components (SI units; the materials are in the decks):
- ``plate_quad``: square plate a = 0.5 m (x, y), CQUAD4 from a transfinite (structured) mesh;
  the steel 5 mm plate of ``tools/analytic`` (ss_plate_modal) so the two paths can be compared;
- ``plate_tria``: the same grids split into CTRIA3 (alternating diagonals);
  both with ``<component>_spc.bdf``: SPC1 set 1, T3 on every edge grid (simple support) and the
  in-plane rigid motion removed by T1, T2 at corner (0, 0) and T2 at corner (a, 0);
- ``beam_hex``: box 1.0 × 0.04 × 0.02 m (x, y, z), CHEXA from a transfinite mesh;
- ``beam_tet10``: the same box, unstructured 10-node CTETRA.

Sizes: "test" plate 16 × 16, beam_hex 40 × 4 × 2, beam_tet10 element size 0.025 m;
"full" plate 48 × 48, beam_hex 120 × 12 × 6, beam_tet10 0.007 m.

``--references`` writes reference/scenes/<deck>.json for the decks in decks/plates/ with the
analytic targets (Navier plate, Euler–Bernoulli free-free beam) and tolerances computed from
the "test" mesh sizes (see :func:`references`).
"""
from __future__ import annotations

import argparse
import json
import math
from pathlib import Path

import gmsh

from paraflex_tools import REPO, analytic, meshing
from paraflex_tools.cards import card

PROVENANCE = "meshes/plates.py"
A = 0.5                          # plate side (m)
T_PLATE = 0.005                  # plate thickness (m), in the decks
BEAM = (1.0, 0.04, 0.02)         # beam L (x), b (y), h (z) in m
SIZES = {
    "test": {"plate": 16, "hex": (40, 4, 2), "tet": 0.025},
    "full": {"plate": 48, "hex": (120, 12, 6), "tet": 0.007},
}
SURFACE, EDGES, CORNER0, CORNER1, VOLUME = 1, 2, 3, 4, 5  # physical group tags
PID = 1


def _transfinite_curves(n_of_length) -> None:
    """Every curve transfinite with n_of_length(curve length) divisions."""
    for dim, tag in gmsh.model.getEntities(1):
        x0, y0, z0, x1, y1, z1 = gmsh.model.getBoundingBox(dim, tag)
        gmsh.model.mesh.setTransfiniteCurve(tag, n_of_length(max(x1 - x0, y1 - y0, z1 - z0)) + 1)


def plate(name: str, n: int, quads: bool, out: Path) -> list[Path]:
    with meshing.gmsh_session(name):
        s = gmsh.model.occ.addRectangle(0.0, 0.0, 0.0, A, A)
        gmsh.model.occ.synchronize()
        _transfinite_curves(lambda length: n)
        gmsh.model.mesh.setTransfiniteSurface(s, "AlternateLeft")
        if quads:
            gmsh.model.mesh.setRecombine(2, s)
        gmsh.model.addPhysicalGroup(2, [s], SURFACE)
        gmsh.model.addPhysicalGroup(1, [t for _, t in gmsh.model.getEntities(1)], EDGES)
        corners = {}
        for _, p in gmsh.model.getEntities(0):
            x, y, _, _, _, _ = gmsh.model.getBoundingBox(0, p)
            corners[(round(x / A), round(y / A))] = p
        gmsh.model.addPhysicalGroup(0, [corners[(0, 0)]], CORNER0)
        gmsh.model.addPhysicalGroup(0, [corners[(1, 0)]], CORNER1)
        gmsh.model.mesh.generate(2)
        mesh = meshing.extract({(2, SURFACE): PID})
        edge, c0, c1 = mesh.grids_of(1, EDGES), mesh.grids_of(0, CORNER0), mesh.grids_of(0, CORNER1)
    mesh_path, spc_path = out / f"{name}.bdf", out / f"{name}_spc.bdf"
    meshing.fit_large_field(mesh)
    meshing.write_mesh_include(mesh, mesh_path, PROVENANCE)
    cards = [card("SPC1", 1, "3", *edge, form="fit"), card("SPC1", 1, "12", *c0, form="fit"),
             card("SPC1", 1, "2", *c1, form="fit")]
    meshing.write_cards(spc_path, PROVENANCE, cards,
                        f"{name}: simple support, SPC set 1: T3 on the {len(edge)} edge grids; "
                        f"T1 T2 at corner (0,0) = grid {c0[0]}, T2 at corner (a,0) = grid {c1[0]}")
    return [mesh_path, spc_path]


def beam(name: str, size, hexa: bool, out: Path) -> list[Path]:
    L, b, h = BEAM
    with meshing.gmsh_session(name):
        v = gmsh.model.occ.addBox(0.0, 0.0, 0.0, L, b, h)
        gmsh.model.occ.synchronize()
        if hexa:
            nx, ny, nz = size
            divisions = {L: nx, b: ny, h: nz}
            _transfinite_curves(lambda length: divisions[min(divisions, key=lambda d: abs(d - length))])
            for _, s in gmsh.model.getEntities(2):
                gmsh.model.mesh.setTransfiniteSurface(s)
                gmsh.model.mesh.setRecombine(2, s)
            gmsh.model.mesh.setTransfiniteVolume(v)
        else:
            gmsh.option.setNumber("Mesh.MeshSizeMin", size)
            gmsh.option.setNumber("Mesh.MeshSizeMax", size)
            gmsh.option.setNumber("Mesh.ElementOrder", 2)
            gmsh.option.setNumber("Mesh.SecondOrderLinear", 1)  # straight edges: exact volume
        gmsh.model.addPhysicalGroup(3, [v], VOLUME)
        gmsh.model.mesh.generate(3)
        mesh = meshing.extract({(3, VOLUME): PID})
    path = out / f"{name}.bdf"
    meshing.fit_large_field(mesh)
    meshing.write_mesh_include(mesh, path, PROVENANCE)
    if not hexa:
        meshing.fix_tetra10_cards(path)
    return [path]


def generate(out: Path, size: str) -> list[Path]:
    """Write the includes of the plate and beam family into ``out``; size "test" or "full"."""
    if size not in SIZES:
        raise ValueError(f"size must be one of {sorted(SIZES)}, got {size!r}")
    s = SIZES[size]
    out.mkdir(parents=True, exist_ok=True)
    return (plate("plate_quad", s["plate"], True, out) + plate("plate_tria", s["plate"], False, out)
            + beam("beam_hex", s["hex"], True, out) + beam("beam_tet10", s["tet"], False, out))


# ---------------------------------------------------------------------------------------------
# analytic references for decks/plates/ (test sizes)
# ---------------------------------------------------------------------------------------------

def _linear_element_error(k: float, h: float, EI: float, kGA: float, mA: float, mI: float) -> float:
    """Relative frequency error of the 1D analogue of the linear shell/solid elements (two-node
    Timoshenko elements, linear w and ψ, one-point shear, consistent mass; paraflex_tools.analytic) for a
    wave of wavenumber k on elements of length h: mode 1 of a simply supported span π/k meshed
    with elements of length ≈ h, against the exact Timoshenko value at the same k."""
    span = math.pi / k
    n = max(1, round(span / h))
    fe = analytic.timoshenko_fe_1d(span, EI, kGA, mA, mI, n, 1, bc="ss")[0]
    exact = analytic.timoshenko_dispersion(k, EI, kGA, mA, mI)
    return (fe - exact) / exact


def plate_reference(deck: str, element: str) -> dict:
    E, nu, rho = (analytic.STEEL[k] for k in ("E", "nu", "rho"))
    t, G, kappa = T_PLATE, E / (2 * (1 + nu)), analytic.KAPPA_SHELL
    D = E * t ** 3 / (12 * (1 - nu ** 2))
    modes = [(1, 1), (1, 2), (2, 1), (2, 2)]
    n = SIZES["test"]["plate"]
    f, terms = [], []
    for m, q in modes:
        k = math.pi / A * math.hypot(m, q)
        fk = math.pi / 2 * (m * m + q * q) / A ** 2 * math.sqrt(D / (rho * t))
        mindlin = analytic.timoshenko_dispersion(k, D, kappa * G * t, rho * t, rho * t ** 3 / 12) / fk - 1
        # x and y errors of the 1D analogue weighted by kx², ky² (as make_cases.py ss_plate_modal)
        ex = [_linear_element_error(j * math.pi / A, A / n, D, kappa * G * t, rho * t, rho * t ** 3 / 12)
              for j in (m, q)]
        disc = (m * m * ex[0] + q * q * ex[1]) / (m * m + q * q)
        f.append(fk)
        terms.append((m, q, mindlin, disc))
    tol = 1.25 * max(abs(mi) + 2 * abs(di) for _, _, mi, di in terms)
    detail = "; ".join(f"({m},{q}) Mindlin {100 * mi:+.2f} %, discretization {100 * di:+.2f} %"
                       for m, q, mi, di in terms)
    return {
        "deck": deck,
        "source": (f"analytic: Navier solution of the simply supported Kirchhoff plate, "
                   f"f_mn = (pi/2)(m^2 + n^2)/a^2 sqrt(D/(rho t)), D = E t^3/(12(1-nu^2)), a = {A} m, "
                   f"t = {t} m, steel E {E:g} Pa, nu {nu}, rho {rho} ({analytic.LEISSA.strip()}); "
                   f"modes (1,1), (1,2), (2,1), (2,2). Mass rho a^2 t (exact for the meshed "
                   f"square). rel_tol = 1.25 x max over the modes of |Mindlin shear + rotary "
                   f"inertia correction (kappa 5/6)| + 2 x |discretization estimate| on the "
                   f"{n} x {n} {element} mesh (h = {A / n:g} m), the estimate from the 1D analogue "
                   f"(linear Timoshenko elements, one-point shear, consistent mass; "
                   f"tools/analytic/make_cases.py), counted twice for the 2D element: {detail}. "
                   f"Generated by meshes/plates.py --references."),
        "mass": {"target": rho * A * A * t, "rel_tol": 1e-9},
        "frequencies": {"target": f, "rel_tol": float(f"{tol:.2g}"), "first_mode": 1},
    }


def beam_reference(deck: str, element: str, h_el: float, note: str) -> dict:
    E, nu, rho = (analytic.STEEL[k] for k in ("E", "nu", "rho"))
    L, b, h = BEAM
    G = E / (2 * (1 + nu))
    kappa = 10 * (1 + nu) / (12 + 11 * nu)  # Cowper, rectangle
    area = b * h
    roots = []
    for guess in (4.73, 7.85):  # 1 - cos(x) cosh(x) = 0, free-free (Blevins Table 8-1)
        x = guess
        for _ in range(50):
            x -= (1 - math.cos(x) * math.cosh(x)) / (math.sin(x) * math.cosh(x) - math.cos(x) * math.sinh(x))
        roots.append(x)
    # modes 7, 8, 9: bending 1 in x-z (I = b h^3/12), bending 1 in x-y, bending 2 in x-z
    modes = [("x-z", b * h ** 3 / 12, roots[0]), ("x-y", h * b ** 3 / 12, roots[0]), ("x-z", b * h ** 3 / 12, roots[1])]
    f, terms = [], []
    for plane, inertia, beta in modes:
        k = beta / L
        fe = beta ** 2 / (2 * math.pi * L ** 2) * math.sqrt(E * inertia / (rho * area))
        timo = analytic.timoshenko_dispersion(k, E * inertia, kappa * G * area, rho * area, rho * inertia) / fe - 1
        disc = _linear_element_error(k, h_el, E * inertia, kappa * G * area, rho * area, rho * inertia)
        f.append(fe)
        terms.append((plane, beta, timo, disc))
    tol = 1.25 * max(abs(ti) + 2 * abs(di) for _, _, ti, di in terms)
    detail = "; ".join(f"{p} beta L {bl:.4f}: Timoshenko {100 * ti:+.2f} %, discretization {100 * di:+.2f} %"
                       for p, bl, ti, di in terms)
    return {
        "deck": deck,
        "source": (f"analytic: Euler-Bernoulli free-free beam, f = (beta L)^2/(2 pi L^2) "
                   f"sqrt(E I/(rho A)), cos(beta L) cosh(beta L) = 1 ({analytic.BLEVINS}), steel "
                   f"E {E:g} Pa, nu {nu}, rho {rho}, box {L} x {b} x {h} m; modes 7-9 = bending 1 "
                   f"in x-z, bending 1 in x-y, bending 2 in x-z (first torsion ~1.2 kHz, axial "
                   f"2.6 kHz lie above). Mass rho L b h (exact for the meshed box). rel_tol = 1.25 "
                   f"x max over the modes of |Timoshenko correction| (shear + rotary inertia, "
                   f"Cowper kappa {kappa:.4f}, from the dispersion relation at k = beta/L; "
                   f"approximate at free ends, hence the margin) + 2 x |discretization "
                   f"estimate| of the 1D linear-element analogue at element length {h_el:g} m "
                   f"({element}; {note}): {detail}. Generated by meshes/plates.py --references."),
        "mass": {"target": rho * L * b * h, "rel_tol": 1e-9},
        "frequencies": {"target": f, "rel_tol": float(f"{tol:.2g}"), "first_mode": 7},
    }


def references() -> list[Path]:
    """Write reference/scenes/<deck>.json for the decks of decks/plates/."""
    s = SIZES["test"]
    refs = {
        "plate_quad_ss": plate_reference("decks/plates/plate_quad_ss.dat", "CQUAD4"),
        "plate_tria_ss": plate_reference("decks/plates/plate_tria_ss.dat", "CTRIA3 (the quad grids, "
                                         "two triangles per square; the quad estimate is used as "
                                         "the triangle's: same grids, linear w and rotations)"),
        "beam_hex_free": beam_reference("decks/plates/beam_hex_free.dat", "CHEXA", BEAM[0] / s["hex"][0],
                                        "incompatible modes make the hexahedron exact in pure "
                                        "bending, so the linear element bounds it"),
        "beam_tet10_free": beam_reference("decks/plates/beam_tet10_free.dat", "CTETRA 10", s["tet"],
                                          "quadratic tetrahedra converge at a higher order than "
                                          "the linear analogue at the same element size, which "
                                          "bounds them"),
    }
    paths = []
    for stem, ref in refs.items():
        path = REPO / "reference" / "scenes" / f"{stem}.json"
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps(ref, indent=1) + "\n")
        paths.append(path)
    return paths


def main() -> None:
    ap = argparse.ArgumentParser(description="plate and beam verification family → Nastran includes")
    ap.add_argument("--size", choices=sorted(SIZES), default="test")
    ap.add_argument("--out", type=Path, help="default meshes/plates/ (test) or meshes/full/plates/ (full)")
    ap.add_argument("--references", action="store_true", help="also write reference/scenes/*.json")
    args = ap.parse_args()
    here = Path(__file__).resolve().parent
    out = args.out or (here / "plates" if args.size == "test" else here / "full" / "plates")
    for p in generate(out, args.size):
        print(p)
    if args.references:
        for p in references():
            print(p)


if __name__ == "__main__":
    main()
