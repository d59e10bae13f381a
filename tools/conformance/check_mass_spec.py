"""Check PYNASTRAN_MASS.md: re-implement pyNastran's mass properties in numpy.

pyNastran is used here only to *parse* the decks (raw card fields: GRID xyz/CP,
CORD2x points/RID, element connectivity, property and material fields, CONM2
fields, PARAM,WTMASS; ``read_bdf(xref=False)``).  Everything else -- grid
positions in the basic system, areas, volumes, mass per area, lumping points,
CONM2 offsets/inertia, the sums, the move to the CG and WTMASS -- follows the
formulas written in tools/conformance/PYNASTRAN_MASS.md, implemented below.

For every ``decks/conformance/*.bdf`` the result is compared with
``pyNastran.bdf.mesh_utils.mass_properties.mass_properties`` and with the stored
``reference/conformance/<stem>.json``; the script prints the max relative
difference (mass; cg relative to max |cg|; inertia relative to max |I|) and
exits non-zero if any exceeds 1e-12.

It then builds small in-memory models that exercise the pyNastran behaviours the
conformance decks deliberately avoid (CONM2 products of inertia, CONM2 inertia
with CID > 0, CONM2 offset in a CORD2C with X2 != 0, a negatively oriented
CTETRA, curved CTETRA10 mid-side grids) and checks that the spec still
reproduces pyNastran there, i.e. that those documented quirks are real.

Run from the repository root:  .venv/bin/python tools/conformance/check_mass_spec.py
"""
from __future__ import annotations

import json
import math
import sys
import warnings
from pathlib import Path

import numpy as np
from pyNastran.bdf.bdf import BDF
from pyNastran.bdf.mesh_utils.mass_properties import mass_properties

REPO = Path(__file__).resolve().parents[2]
DECK_DIR = REPO / "decks" / "conformance"
REF_DIR = REPO / "reference" / "conformance"
TOL = 1e-12

warnings.filterwarnings("ignore", message=r"CONM2 \(eid=\d+\) inertia method")


# --------------------------------------------------------------------------
# coordinate systems (PYNASTRAN_MASS.md section 2)
# --------------------------------------------------------------------------
class Geometry:
    def __init__(self, model: BDF):
        self.model = model
        self._axes: dict[int, tuple[np.ndarray, np.ndarray]] = {}
        self._pos: dict[int, np.ndarray] = {}

    def axes(self, cid: int) -> tuple[np.ndarray, np.ndarray]:
        """(origin, T) with T rows = unit vectors i, j, k of `cid` in basic."""
        if cid == 0:
            return np.zeros(3), np.eye(3)
        if cid not in self._axes:
            coord = self.model.coords[cid]
            assert coord.type in ("CORD2R", "CORD2C", "CORD2S"), coord.type
            e1, e2, e3 = (np.asarray(e, dtype=float) for e in (coord.e1, coord.e2, coord.e3))
            rid = coord.rid
            if rid != 0:
                e1, e2, e3 = (self.to_basic(rid, e) for e in (e1, e2, e3))
            k = (e2 - e1) / np.linalg.norm(e2 - e1)
            jdir = np.cross(k, e3 - e1)
            j = jdir / np.linalg.norm(jdir)
            i = np.cross(j, k)
            self._axes[cid] = (e1, np.vstack([i, j, k]))
        return self._axes[cid]

    def local_cartesian(self, cid: int, p: np.ndarray) -> np.ndarray:
        kind = self.model.coords[cid].type[-1]
        if kind == "R":
            return p
        if kind == "C":                       # (R, theta deg, z)
            r, theta = p[0], math.radians(p[1])
            return np.array([r * math.cos(theta), r * math.sin(theta), p[2]])
        r, theta, phi = p[0], math.radians(p[1]), math.radians(p[2])   # S
        return np.array([r * math.sin(theta) * math.cos(phi),
                         r * math.sin(theta) * math.sin(phi), r * math.cos(theta)])

    def to_basic(self, cid: int, p) -> np.ndarray:
        p = np.asarray(p, dtype=float)
        if cid == 0:
            return p
        origin, t = self.axes(cid)
        return self.local_cartesian(cid, p) @ t + origin

    def grid(self, nid: int) -> np.ndarray:
        if nid not in self._pos:
            node = self.model.nodes[nid]
            self._pos[nid] = self.to_basic(node.cp, node.xyz)
        return self._pos[nid]


# --------------------------------------------------------------------------
# element mass and lumping point (PYNASTRAN_MASS.md section 3)
# --------------------------------------------------------------------------
def shell_mass_per_area(model: BDF, elem, n_corners: int) -> float:
    prop = model.properties[elem.pid]
    if prop.type == "PSHELL":
        mid = prop.mid1 if prop.mid1 is not None else prop.mid2
        rho = model.materials[mid].rho
        t0 = prop.t
        tscales = [elem.T1, elem.T2, elem.T3] + ([elem.T4] if n_corners == 4 else [])
        if elem.tflag == 0:
            t = sum(ti if ti is not None else t0 for ti in tscales) / n_corners
        else:
            t = sum(ti * t0 if ti is not None else t0 for ti in tscales) / n_corners
        return prop.nsm + rho * t
    if prop.type == "PCOMP":
        rhot = 0.0
        for mid, ti in zip(prop.mids, prop.thicknesses):
            rhot += model.materials[mid].rho * ti
        if prop.lam == "SYM":
            return 2.0 * rhot + prop.nsm
        return rhot + prop.nsm
    raise NotImplementedError(prop.type)


def element_mass_point(model: BDF, geo: Geometry, elem) -> tuple[float, np.ndarray]:
    p = [geo.grid(n) for n in elem.nodes if n is not None]
    etype = elem.type
    if etype == "CQUAD4":
        p1, p2, p3, p4 = p[:4]
        centroid = (p1 + p2 + p3 + p4) / 4.0
        mpa = shell_mass_per_area(model, elem, 4)
        if mpa == 0.0:
            return 0.0, centroid
        area = 0.5 * np.linalg.norm(np.cross(p3 - p1, p4 - p2))
        return mpa * area, centroid
    if etype == "CTRIA3":
        p1, p2, p3 = p[:3]
        centroid = (p1 + p2 + p3) / 3.0
        mpa = shell_mass_per_area(model, elem, 3)
        if mpa == 0.0:
            return 0.0, centroid
        area = 0.5 * np.linalg.norm(np.cross(p1 - p2, p1 - p3))
        return mpa * area, centroid
    if etype in ("CTETRA", "CPENTA", "CHEXA"):
        rho = model.materials[model.properties[elem.pid].mid].rho
        if etype == "CTETRA":
            p1, p2, p3, p4 = p[:4]                 # mid-side grids ignored
            volume = -np.dot(p1 - p4, np.cross(p2 - p4, p3 - p4)) / 6.0   # signed
            centroid = (p1 + p2 + p3 + p4) / 4.0
        elif etype == "CPENTA":
            assert len(p) == 6, "CPENTA15 not covered"
            p1, p2, p3, p4, p5, p6 = p
            a1 = 0.5 * np.linalg.norm(np.cross(p3 - p1, p2 - p1))
            a2 = 0.5 * np.linalg.norm(np.cross(p6 - p4, p5 - p4))
            c1 = (p1 + p2 + p3) / 3.0
            c2 = (p4 + p5 + p6) / 3.0
            volume = abs((a1 + a2) / 2.0 * np.linalg.norm(c1 - c2))
            centroid = (c1 + c2) / 2.0
        else:
            assert len(p) == 8, "CHEXA20 not covered"
            p1, p2, p3, p4, p5, p6, p7, p8 = p
            a1 = 0.5 * np.linalg.norm(np.cross(p3 - p1, p4 - p2))
            a2 = 0.5 * np.linalg.norm(np.cross(p7 - p5, p8 - p6))
            c1 = (p1 + p2 + p3 + p4) / 4.0
            c2 = (p5 + p6 + p7 + p8) / 4.0
            volume = abs((a1 + a2) / 2.0 * np.linalg.norm(c1 - c2))
            centroid = (c1 + c2) / 2.0
        if rho == 0.0:
            return 0.0, centroid
        return rho * volume, centroid
    if etype in ("CELAS1", "CELAS2", "CELAS3", "CELAS4"):
        return 0.0, np.zeros(3)
    raise NotImplementedError(etype)


def conm2_point_inertia(geo: Geometry, conm2, nastran: frozenset = frozenset()
                        ) -> tuple[float, np.ndarray, np.ndarray]:
    """mass, lumping point, [dIxx, dIyy, dIzz, dIxy, dIxz, dIyz] (section 4).

    `nastran` switches individual pyNastran quirks to the Nastran QRG meaning
    (only used to show that the quirks matter): "products" adds +I21 (QRG:
    I21 = integral of x*y dm), "cid_inertia" rotates the inertia of a CID > 0
    CONM2 into basic, "cyl_offset" takes X in the local Cartesian axes
    (e_r, e_theta, e_z) at the grid instead of as (R, theta, z).
    """
    x = np.asarray(conm2.X, dtype=float)
    cid = conm2.cid
    if cid == 0:
        point = geo.grid(conm2.nid) + x
    elif cid == -1:
        point = x
    else:
        origin, t = geo.axes(cid)
        kind = geo.model.coords[cid].type[-1]
        if "cyl_offset" in nastran and kind == "C":
            local = (geo.grid(conm2.nid) - origin) @ t.T
            theta = math.atan2(local[1], local[0])
            e_r = np.array([math.cos(theta), math.sin(theta), 0.0])
            e_t = np.array([-math.sin(theta), math.cos(theta), 0.0])
            axes = np.vstack([e_r, e_t, [0.0, 0.0, 1.0]]) @ t
            point = geo.grid(conm2.nid) + x @ axes
        else:
            point = geo.grid(conm2.nid) + (geo.to_basic(cid, x) - origin)
    i11, i21, i22, i31, i32, i33 = conm2.I
    sign = 1.0 if "products" in nastran else -1.0
    if cid in (0, -1):
        d_inertia = np.array([i11, i22, i33, sign * i21, sign * i31, sign * i32])
    elif "cid_inertia" in nastran:
        _, t = geo.axes(cid)
        j_local = np.array([[i11, -i21, -i31], [-i21, i22, -i32], [-i31, -i32, i33]])
        j = t.T @ j_local @ t
        d_inertia = np.array([j[0, 0], j[1, 1], j[2, 2], -j[0, 1], -j[0, 2], -j[1, 2]])
    else:
        d_inertia = np.zeros(6)
    return conm2.mass, point, d_inertia


def spec_mass_properties(model: BDF, nastran: frozenset = frozenset()
                         ) -> tuple[float, np.ndarray, np.ndarray]:
    geo = Geometry(model)
    mass = 0.0
    first = np.zeros(3)                # sum m * p
    inertia = np.zeros(6)              # about the basic origin
    items = [(e, None) for e in model.elements.values()]
    items += [(m, "mass") for m in model.masses.values()]
    for item, kind in items:
        if kind == "mass":
            assert item.type == "CONM2", item.type
            m, point, d_inertia = conm2_point_inertia(geo, item, nastran)
        else:
            m, point = element_mass_point(model, geo, item)
            d_inertia = np.zeros(6)
        if m != 0.0:
            x, y, z = point
            inertia += m * np.array([y * y + z * z, x * x + z * z, x * x + y * y,
                                     x * y, x * z, y * z])
            mass += m
            first += m * point
        inertia += d_inertia
    cg = first / mass if mass else first
    cx, cy, cz = cg
    inertia -= mass * np.array([cy * cy + cz * cz, cx * cx + cz * cz, cx * cx + cy * cy,
                                cx * cy, cx * cz, cy * cz])
    wtmass = model.params["WTMASS"].values[0] if "WTMASS" in model.params else 1.0
    return mass * wtmass, cg, inertia * wtmass


# --------------------------------------------------------------------------
def tensor(i6) -> np.ndarray:
    ixx, iyy, izz, ixy, ixz, iyz = i6
    return np.array([[ixx, -ixy, -ixz], [-ixy, iyy, -iyz], [-ixz, -iyz, izz]])


def rel_diff(a, b) -> float:
    (ma, ca, ia), (mb, cb, ib) = a, b
    ca, cb, ia, ib = (np.asarray(v, dtype=float) for v in (ca, cb, ia, ib))
    d_mass = abs(ma - mb) / max(abs(ma), 1e-300)
    d_cg = np.max(np.abs(ca - cb)) / max(np.max(np.abs(ca)), 1e-300)
    d_in = np.max(np.abs(ia - ib)) / max(np.max(np.abs(ia)), 1e-300)
    return float(max(d_mass, d_cg, d_in))


def load(path: Path, xref: bool) -> BDF:
    model = BDF(debug=None)
    model.log.level = "error"
    model.read_bdf(str(path), xref=xref, punch=None)   # meshio decks are bulk-only
    return model


def check_decks() -> float:
    worst = 0.0
    decks = sorted(DECK_DIR.glob("*.bdf"))
    print(f"{'deck':28s} {'vs pyNastran':>13s} {'vs reference':>13s}")
    for deck in decks:
        spec = spec_mass_properties(load(deck, xref=False))
        spec_t = (spec[0], spec[1], tensor(spec[2]))
        mass, cg, i6 = mass_properties(load(deck, xref=True))
        d_py = rel_diff(spec_t, (mass, cg, tensor(i6)))
        ref = json.loads((REF_DIR / f"{deck.stem}.json").read_text())
        d_ref = rel_diff(spec_t, (ref["mass"], ref["cg"], ref["inertia_cg"]))
        worst = max(worst, d_py, d_ref)
        print(f"{deck.stem:28s} {d_py:13.3e} {d_ref:13.3e}")
    return worst


def quirk_model() -> BDF:
    """Cases the decks avoid on purpose; each is a documented pyNastran quirk."""
    model = BDF(debug=None)
    model.log.level = "error"
    model.add_cord2r(10, [1.0, 2.0, 3.0], [1.0, 2.0, 4.0], [2.0, 2.5, 3.0])
    model.add_cord2c(20, [0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [1.0, 0.0, 0.0])
    pts = {1: [0.0, 0.0, 0.0], 2: [1.0, 0.0, 0.0], 3: [0.0, 1.0, 0.0], 4: [0.0, 0.0, 1.0],
           5: [2.0, 0.0, 0.0], 6: [3.0, 0.0, 0.0], 7: [2.0, 1.0, 0.0], 8: [2.0, 0.0, 1.0]}
    for nid, xyz in pts.items():
        model.add_grid(nid, xyz)
    model.add_grid(9, [1.0, 30.0, 0.5], cp=20)
    # curved CTETRA10: mid-side grids off the edge midpoints (ignored)
    for nid, xyz in {11: [1.6, 0.1, 0.0], 12: [2.6, 0.6, 0.1], 13: [2.0, 0.5, 0.2],
                     14: [2.0, 0.1, 0.5], 15: [2.5, 0.1, 0.6], 16: [2.1, 0.6, 0.5]}.items():
        model.add_grid(nid, xyz)
    model.add_mat1(1, 2.1e11, None, 0.3, rho=1.5)
    model.add_psolid(1, 1)
    model.add_ctetra(1, 1, [1, 3, 2, 4])          # negative orientation
    model.add_ctetra(2, 1, [5, 6, 7, 8, 11, 12, 13, 14, 15, 16])
    # CONM2 products of inertia (sign), inertia with CID > 0 (dropped),
    # offset in a CORD2C with X2 != 0 (read as R, theta, z)
    model.add_conm2(101, 1, 2.0, cid=0, X=[0.1, 0.2, 0.3], I=[1.0, 0.3, 2.0, 0.2, 0.1, 3.0])
    model.add_conm2(102, 2, 3.0, cid=10, X=[0.5, 0.0, 0.0], I=[1.0, 0.1, 1.0, 0.1, 0.1, 1.0])
    model.add_conm2(103, 9, 1.5, cid=20, X=[0.2, 45.0, 0.1])
    model.add_conm2(104, 3, 1.0, cid=-1, X=[5.0, 5.0, 5.0], I=[0.5, 0.05, 0.6, 0.0, 0.0, 0.7])
    return model


def check_quirks() -> float:
    model = quirk_model()
    spec = spec_mass_properties(model)
    model.cross_reference()
    mass, cg, i6 = mass_properties(model)
    d = rel_diff((spec[0], spec[1], tensor(spec[2])), (mass, cg, tensor(i6)))
    print(f"{'quirk model (in memory)':28s} {d:13.3e}")
    # and the quirks are really there: each Nastran-QRG reading moves the result
    for quirk in ("products", "cid_inertia", "cyl_offset"):
        alt = spec_mass_properties(model, frozenset([quirk]))
        d_alt = rel_diff((alt[0], alt[1], tensor(alt[2])), (mass, cg, tensor(i6)))
        print(f"  with Nastran meaning of {quirk!r:14s}: {d_alt:9.3e} (must be > 0)")
        assert d_alt > 1e-6, quirk
    tet4, tet10 = model.elements[1], model.elements[2]
    assert tet4.Volume() < 0.0, "negatively oriented CTETRA: negative volume kept"
    corners = [model.nodes[n].xyz for n in tet10.node_ids[:4]]
    v4 = -np.dot(corners[0] - corners[3],
                 np.cross(corners[1] - corners[3], corners[2] - corners[3])) / 6.0
    assert tet10.Volume() == v4, "CTETRA10 volume uses the 4 corners only"
    return d


def main() -> int:
    worst = check_decks()
    worst = max(worst, check_quirks())
    print(f"\nmax relative difference: {worst:.3e} (tolerance {TOL:g})")
    return 0 if worst <= TOL else 1


if __name__ == "__main__":
    sys.exit(main())
