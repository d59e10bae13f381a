#!/usr/bin/env python3
"""Solid stresses of paraflex's CHEXA (STRESS output: centroid and corner stresses) against
CalculiX C3D8I on the same mesh.

Model: the steel cantilever of solid_same_mesh.py (1.0 x 0.1 x 0.1 m, 10 x 2 x 2 bricks, root
x = 0 fixed in T1-T3, tip loads FY = 300 N and FZ = 1000 N shared by the tip grids), meshed with
CHEXA (paraflex, incompatible modes) and C3D8I (ccx, the same Wilson-Taylor incompatible-mode
brick). ccx prints the stresses at the 2 x 2 x 2 integration points of every element
(*EL PRINT, S); this script turns them into what paraflex writes, by its own code:

- centroid: the mean of the 8 integration-point stresses (on these undistorted bricks the centre
  value of the trilinear field through the points, which is what the element's strain at its
  centre gives: the incompatible modes' gradients are odd in the natural coordinates and the
  compatible strain's bilinear terms average out);
- corners: the trilinear Lagrange interpolant through the 8 points evaluated at the 8 corners
  (natural coordinates ±1, i.e. ±√3 in the points' own coordinates), the extrapolation ccx and
  Nastran's CORNER output use.

ccx integration-point order (gauss3d2): ξ fastest, then η, then ζ, each -1/√3 before +1/√3; its
brick corner order is Nastran's CHEXA order, so the natural axes coincide. ccx stress columns
sxx syy szz sxy sxz syz are written as paraflex's σxx σyy σzz τxy τyz τzx.

Writes decks/verify/solid/cantilever_chexa_stress.dat and
reference/calculix/solid/cantilever_chexa_stress.json. Run:
    .venv/bin/python tools/calculix/solid_stress.py
"""

import itertools
import json
import re

import numpy as np

import solid_same_mesh as same

CASE = "cantilever_chexa_stress"
G = 1.0 / np.sqrt(3.0)
# ccx gauss3d2 order: ξ fastest
POINTS = [(x, y, z) for z in (-G, G) for y in (-G, G) for x in (-G, G)]
# CHEXA / C3D8 corner order in natural coordinates
CORNERS = [(-1, -1, -1), (1, -1, -1), (1, 1, -1), (-1, 1, -1),
           (-1, -1, 1), (1, -1, 1), (1, 1, 1), (-1, 1, 1)]


def hexa_mesh():
    nid, nodes = same.corner_grid()
    elems = []
    for k, j, i in itertools.product(range(same.NZ), range(same.NY), range(same.NX)):
        elems.append([nid(i, j, k), nid(i + 1, j, k), nid(i + 1, j + 1, k), nid(i, j + 1, k),
                      nid(i, j, k + 1), nid(i + 1, j, k + 1), nid(i + 1, j + 1, k + 1),
                      nid(i, j + 1, k + 1)])
    return nodes, elems


def lagrange_at(xi):
    """Values at `xi` of the trilinear Lagrange functions of the 8 integration points."""
    return np.array([np.prod([(1 + xi[d] * np.sign(p[d]) / G) / 2 for d in range(3)])
                     for p in POINTS])


def element_stresses(dat: str, n_elems: int):
    """ccx *EL PRINT S: element -> 8 x 6 (integration points, paraflex order)."""
    num = same.NUMBER
    pat = re.compile(rf"^\s*(\d+)\s+(\d+)" + rf"\s+({num})" * 6 + r"\s*$")
    out = {e: np.zeros((8, 6)) for e in range(1, n_elems + 1)}
    block = dat[dat.index("stresses (elem"):]
    for line in block.splitlines()[1:]:
        m = pat.match(line)
        if m:
            e, q = int(m.group(1)), int(m.group(2))
            sxx, syy, szz, sxy, sxz, syz = (float(m.group(k)) for k in range(3, 9))
            out[e][q - 1] = [sxx, syy, szz, sxy, syz, sxz]
    return out


def main():
    nodes, elems = hexa_mesh()
    deck = same.nastran_deck(CASE, "CHEXA", nodes, elems, static=True)
    deck = deck.replace("solid_same_mesh.py", "solid_stress.py").replace(
        "DISPLACEMENT = ALL", "DISPLACEMENT = ALL\nSTRESS = ALL")
    (same.DECKS / f"{CASE}.dat").write_text(deck)
    inp = same.ccx_input("C3D8I", nodes, elems, static=True)
    inp = inp.replace("*END STEP", "*EL PRINT, ELSET=EALL\nS\n*END STEP")
    (same.WORK).mkdir(parents=True, exist_ok=True)
    (same.WORK / f"{CASE}.inp").write_text(inp)
    dat = same.run_ccx(CASE)
    ip = element_stresses(dat, len(elems))
    if any(not np.any(v) for v in ip.values()):
        raise RuntimeError("an element has no stresses in the ccx output")
    extrapolate = np.array([lagrange_at(c) for c in CORNERS])  # 8 corners x 8 points
    assert np.allclose(extrapolate.sum(axis=1), 1.0)
    assert np.allclose(np.array([lagrange_at(p) for p in POINTS]), np.eye(8))
    elements = []
    for e, conn in enumerate(elems, 1):
        elements.append({
            "id": e,
            "grids": conn,
            "centroid": list(ip[e].mean(axis=0)),
            "corners": (extrapolate @ ip[e]).tolist(),
        })
    ref = {
        "case": CASE,
        "deck": f"decks/verify/solid/{CASE}.dat",
        "provenance": {
            "code": same.ccx_version(),
            "element": "C3D8I (incompatible modes), same mesh and grid numbering",
            "command": "ccx -i cantilever_chexa_stress (single-threaded), *STATIC, *EL PRINT S",
            "how": "integration-point stresses of the ccx .dat; centroid = their mean, corners = the trilinear interpolant through them at the corners (see tools/calculix/solid_stress.py)",
        },
        "units": "Pa; stress order sxx syy szz txy tyz tzx (basic)",
        "elements": elements,
        "tolerance": {
            "rel": 1e-6,
            "of": "the largest |stress| of the reference (max over elements and components)",
            "why": "same mesh, same element (Wilson-Taylor incompatible-mode brick): on undistorted bricks the two codes solve the same discrete problem, so only the solvers' round-off and ccx's printed digits (about 7) remain",
        },
    }
    (same.REFS / f"{CASE}.json").write_text(json.dumps(ref, indent=1) + "\n")
    smax = max(np.abs(np.array(el["corners"])).max() for el in elements)
    print(f"wrote {CASE}: {len(elems)} elements, max |corner stress| {smax:.4e} Pa")


if __name__ == "__main__":
    main()
