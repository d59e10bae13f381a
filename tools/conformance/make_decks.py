"""Build the deck-reader conformance decks with pyNastran's card API.

Produces, under ``decks/conformance/``, six small SOL 103 models, each written
three ways (same model, same values):

* ``<name>_small.bdf`` -- ``BDF.write_bdf(size=8)`` (8-character fields)
* ``<name>_large.bdf`` -- ``BDF.write_bdf(size=16)`` (16-character ``*`` fields;
  pyNastran still writes a few cards, e.g. CELAS1/CELAS2/PELAS/RBE2/SPC1, in
  small field, so these decks mix both formats)
* ``<name>_free.bdf``  -- the small-field deck converted card by card to free
  field: ``NAME,f2,...,f9`` then ``+,f10,...,f17`` continuation lines (8 data
  fields a line, each field at most 8 characters, as MSC requires)

Models:

* ``plate_pshell``   distorted, slightly warped CQUAD4 plate + a CTRIA3 strip,
                     PSHELL with NSM, one membrane-only PSHELL, CTRIA3/CQUAD4
                     with corner thicknesses (TFLAG 0 and 1), THETA/ZOFFS
* ``pcomp_plate``    angle-ply CQUAD4/CTRIA3 plate, two PCOMPs with 8 plies
                     (+-theta), one written with LAM=SYM (4 plies + mirror),
                     MAT8, MCID through a rotated CORD2R
* ``solid_hexa``     distorted (non-rectangular) CHEXA block + CPENTA column,
                     PSOLID/MAT1, the only deck with PARAM,WTMASS
* ``solid_tetra``    CTETRA 4-node block (6 tets per cell) + a separate
                     CTETRA 10-node block (mid-side grids at edge midpoints)
* ``conm2_coords``   grids in a rotated CORD2R, a CORD2C and a CORD2C nested in
                     the CORD2R (CP != 0), cylindrical CQUAD4 panel, CONM2 with
                     CID = 0, -1, rotated CORD2R and CORD2C
* ``mixed``          all of the above in one deck + RBE2, RBE3, CELAS1/PELAS,
                     CELAS2

Every deck: ``SOL 103`` / ``CEND`` / case control (``TITLE``, ``METHOD = 1``,
``SPC = 1``) / ``BEGIN BULK`` ... ``EIGRL 1`` ... ``ENDDATA``.  pyNastran sorts
the case-control lines alphabetically when writing.

Values are chosen so that each one is exact in 8 characters (coordinates on a
1e-4 grid, etc.), so the small, large and free decks of a model hold the same
numbers -- except ``conm2_coords``, whose CORD2R/CORD2C points carry full
double precision on purpose (the large-field deck keeps more digits than the
small/free ones, so its reference differs in the last digits).

CONM2 cards are restricted to the cases where pyNastran's mass properties agree
with the Nastran definition (see PYNASTRAN_MASS.md): no products of inertia,
no inertia when CID > 0, and the CORD2C offset has X2 = 0 at a grid lying at
theta = 0 of that system.

Deterministic: pseudo-random distortions come from numpy's legacy
``RandomState`` with fixed seeds and are rounded to 4 decimals.

Run from the repository root:  .venv/bin/python tools/conformance/make_decks.py
"""
from __future__ import annotations

import io
import math
from pathlib import Path

import numpy as np
from pyNastran.bdf.bdf import BDF
from pyNastran.bdf.bdf_interface.utils import to_fields

from paraflex_tools.cards import card as free_card
from pyNastran.bdf.case_control_deck import CaseControlDeck

REPO = Path(__file__).resolve().parents[2]
OUT_DIR = REPO / "decks" / "conformance"


def r4(value: float) -> float:
    """Round to 4 decimals so the value prints exactly in 8 characters."""
    return float(round(float(value), 4))


def new_model(title: str, with_spc: bool = True) -> BDF:
    model = BDF(debug=None, log=None, mode="msc")
    model.sol = 103
    model.executive_control_lines = ["SOL 103", "CEND"]
    lines = [f"TITLE = paraflex conformance: {title}", "METHOD = 1"]
    if with_spc:
        lines.append("SPC = 1")
    lines.append("BEGIN BULK")
    model.case_control_deck = CaseControlDeck(lines, log=model.log)
    model.add_eigrl(1, nd=10)
    return model


# --------------------------------------------------------------------------
# parts: each adds cards to `model`; ids are offset by the given bases
# --------------------------------------------------------------------------
def add_shell_plate(model: BDF, nid0: int, eid0: int, pid0: int, mid: int,
                    origin=(0.0, 0.0, 0.0), nx: int = 8, ny: int = 6,
                    seed: int = 1, variable_thickness: bool = True) -> dict:
    """Distorted, slightly warped CQUAD4 plate; the last column is CTRIA3."""
    rng = np.random.RandomState(seed)
    nid = {}
    for j in range(ny):
        for i in range(nx):
            x = origin[0] + 0.25 * i + (rng.uniform(-0.04, 0.04) if 0 < i < nx - 1 else 0.0)
            y = origin[1] + 0.20 * j + (rng.uniform(-0.03, 0.03) if 0 < j < ny - 1 else 0.0)
            z = origin[2] + rng.uniform(-0.004, 0.004)       # slight warp
            n = nid0 + 100 * (j + 1) + (i + 1)                # gaps on purpose
            model.add_grid(n, [r4(x), r4(y), r4(z)])
            nid[i, j] = n
    pshell = pid0
    pmem = pid0 + 1
    model.add_pshell(pshell, mid1=mid, t=0.002, mid2=mid, mid3=mid, nsm=0.35)
    model.add_pshell(pmem, mid1=mid, t=0.0015, nsm=0.0)     # membrane only
    eid = eid0
    quads, trias = [], []
    for j in range(ny - 1):
        for i in range(nx - 1):
            n1, n2, n3, n4 = nid[i, j], nid[i + 1, j], nid[i + 1, j + 1], nid[i, j + 1]
            if i < nx - 2:
                eid += 1
                kwargs = {}
                if (i + j) % 5 == 1:
                    kwargs = {"theta_mcid": 15.0, "zoffset": 0.0005}
                if variable_thickness and (i, j) == (2, 1):
                    kwargs = {"tflag": 1, "T1": 1.1, "T2": 0.9, "T3": 1.2, "T4": 0.8}
                model.add_cquad4(eid, pshell, [n1, n2, n3, n4], **kwargs)
                quads.append(eid)
            else:
                eid += 1
                kwargs = {}
                if variable_thickness and j == 1:
                    kwargs = {"tflag": 0, "T1": 0.0012, "T2": 0.0018, "T3": 0.0016}
                model.add_ctria3(eid, pmem, [n1, n2, n3], **kwargs)
                eid += 1
                model.add_ctria3(eid, pshell, [n1, n3, n4], theta_mcid=30.0)
                trias += [eid - 1, eid]
    return {"nid": nid, "eid_end": eid, "quads": quads, "trias": trias}


def add_pcomp_plate(model: BDF, nid0: int, eid0: int, pid0: int, mid0: int,
                    mcid: int, origin=(0.0, 0.0, 0.0), nx: int = 7, ny: int = 5,
                    seed: int = 2) -> dict:
    """Angle-ply plate: PCOMP (8 plies listed) and PCOMP LAM=SYM (4 + mirror)."""
    rng = np.random.RandomState(seed)
    carbon, glass = mid0, mid0 + 1
    model.add_mat8(carbon, 1.4e11, 9.0e9, 0.3, g12=5.0e9, g1z=4.5e9, g2z=3.0e9,
                   rho=1600.0)
    model.add_mat8(glass, 4.5e10, 1.2e10, 0.28, g12=4.5e9, g1z=4.0e9, g2z=3.5e9,
                   rho=1950.0)
    theta = 30.0
    p_full, p_sym = pid0, pid0 + 1
    model.add_pcomp(p_full,
                    mids=[carbon, carbon, glass, carbon, carbon, glass, carbon, carbon],
                    thicknesses=[1.25e-4, 1.25e-4, 2.0e-4, 1.25e-4,
                                 1.25e-4, 2.0e-4, 1.25e-4, 1.25e-4],
                    thetas=[theta, -theta, theta, -theta, -theta, theta, -theta, theta],
                    souts=["YES"] * 8, nsm=0.12, z0=-0.0006)
    model.add_pcomp(p_sym,
                    mids=[carbon, glass, carbon, carbon],
                    thicknesses=[1.5e-4, 2.5e-4, 1.5e-4, 1.0e-4],
                    thetas=[45.0, -45.0, 45.0, -45.0],
                    nsm=0.05, lam="SYM")
    nid = {}
    for j in range(ny):
        for i in range(nx):
            x = origin[0] + 0.3 * i + (rng.uniform(-0.05, 0.05) if 0 < i < nx - 1 else 0.0)
            y = origin[1] + 0.25 * j + (rng.uniform(-0.04, 0.04) if 0 < j < ny - 1 else 0.0)
            z = origin[2] + rng.uniform(-0.003, 0.003)
            n = nid0 + 50 * j + 2 * i + 1                     # odd ids only
            model.add_grid(n, [r4(x), r4(y), r4(z)])
            nid[i, j] = n
    eid = eid0
    elems = []
    for j in range(ny - 1):
        for i in range(nx - 1):
            n1, n2, n3, n4 = nid[i, j], nid[i + 1, j], nid[i + 1, j + 1], nid[i, j + 1]
            pid = p_full if i < (nx - 1) // 2 else p_sym
            if (i, j) in ((5, 0), (5, 3)):
                eid += 1
                model.add_ctria3(eid, pid, [n1, n2, n4], theta_mcid=mcid)
                eid += 1
                model.add_ctria3(eid, pid, [n2, n3, n4])
                elems += [eid - 1, eid]
                continue
            eid += 1
            theta_mcid = mcid if (i + j) % 3 == 0 else float(10 * ((i + j) % 4))
            zoffset = -0.0002 if (i + j) % 4 == 2 else 0.0
            model.add_cquad4(eid, pid, [n1, n2, n3, n4], theta_mcid=theta_mcid,
                             zoffset=zoffset)
            elems.append(eid)
    return {"nid": nid, "eid_end": eid, "elems": elems}


def add_hexa_penta_block(model: BDF, nid0: int, eid0: int, pid0: int, mid0: int,
                         origin=(0.0, 0.0, 0.0), nx: int = 5, ny: int = 4,
                         nz: int = 3, seed: int = 3,
                         rho_hexa: float = 2700.0, rho_penta: float = 7850.0) -> dict:
    """Distorted CHEXA block; cells of column i = nx-2 are split into 2 CPENTA."""
    rng = np.random.RandomState(seed)
    model.add_mat1(mid0, 7.0e10, None, 0.33, rho=rho_hexa)
    model.add_mat1(mid0 + 1, 2.1e11, None, 0.29, rho=rho_penta)
    model.add_psolid(pid0, mid0)
    model.add_psolid(pid0 + 1, mid0 + 1)
    nid = {}
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                # shear + taper so no cell is a rectangular box
                x = origin[0] + 0.5 * i + 0.08 * k + 0.03 * j + rng.uniform(-0.06, 0.06)
                y = origin[1] + (0.4 + 0.02 * i) * j + rng.uniform(-0.05, 0.05)
                z = origin[2] + 0.3 * k + 0.02 * i + rng.uniform(-0.04, 0.04)
                n = nid0 + 1000 * k + 20 * j + i + 1
                model.add_grid(n, [r4(x), r4(y), r4(z)])
                nid[i, j, k] = n
    eid = eid0
    hexas, pentas = [], []
    for k in range(nz - 1):
        for j in range(ny - 1):
            for i in range(nx - 1):
                a, b = nid[i, j, k], nid[i + 1, j, k]
                c, d = nid[i + 1, j + 1, k], nid[i, j + 1, k]
                e, f = nid[i, j, k + 1], nid[i + 1, j, k + 1]
                g, h = nid[i + 1, j + 1, k + 1], nid[i, j + 1, k + 1]
                if i == nx - 2:
                    eid += 1
                    model.add_cpenta(eid, pid0 + 1, [a, b, c, e, f, g])
                    eid += 1
                    model.add_cpenta(eid, pid0 + 1, [a, c, d, e, g, h])
                    pentas += [eid - 1, eid]
                else:
                    eid += 1
                    model.add_chexa(eid, pid0, [a, b, c, d, e, f, g, h])
                    hexas.append(eid)
    return {"nid": nid, "eid_end": eid, "hexas": hexas, "pentas": pentas}


def _signed_volume(p1, p2, p3, p4) -> float:
    return float(np.dot(p2 - p1, np.cross(p3 - p1, p4 - p1)) / 6.0)


# Kuhn split of a cube (corner index bits: x=1, y=2, z=4) into 6 tets along 0-7
_KUHN = [(0, 1, 3, 7), (0, 1, 5, 7), (0, 2, 3, 7), (0, 2, 6, 7), (0, 4, 5, 7), (0, 4, 6, 7)]


def add_tetra_block(model: BDF, nid0: int, eid0: int, pid: int, mid: int,
                    origin=(0.0, 0.0, 0.0), n: tuple = (4, 3, 3), seed: int = 4,
                    tet10: bool = False, rho: float = 7850.0) -> dict:
    """Distorted box split into positively oriented tets (4- or 10-node)."""
    rng = np.random.RandomState(seed)
    model.add_mat1(mid, 2.1e11, None, 0.3, rho=rho)
    model.add_psolid(pid, mid)
    nx, ny, nz = n
    nid, xyz = {}, {}
    for k in range(nz):
        for j in range(ny):
            for i in range(nx):
                d = rng.uniform(-0.05, 0.05, 3)
                # corners on a 2e-3 grid so that edge midpoints stay exact in 8 chars
                p = np.round((np.array(origin) + [0.4 * i, 0.35 * j, 0.3 * k + 0.02 * i] + d) / 0.002) * 0.002
                p = np.array([r4(v) for v in p])
                g = nid0 + 100 * k + 10 * j + i + 1
                model.add_grid(g, p.tolist())
                nid[i, j, k], xyz[g] = g, p
    eid = eid0
    elems = []
    mid_nodes = {}
    next_mid = nid0 + 5000
    for k in range(nz - 1):
        for j in range(ny - 1):
            for i in range(nx - 1):
                corner = [nid[i + (c & 1), j + ((c >> 1) & 1), k + ((c >> 2) & 1)]
                          for c in range(8)]
                for tet in _KUHN:
                    g = [corner[c] for c in tet]
                    if _signed_volume(*(xyz[x] for x in g)) < 0.0:
                        g[1], g[2] = g[2], g[1]
                    nodes = list(g)
                    if tet10:
                        # Nastran CTETRA order: G5..G10 on edges 1-2, 2-3, 3-1, 1-4, 2-4, 3-4
                        for a, b in ((0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)):
                            key = tuple(sorted((g[a], g[b])))
                            if key not in mid_nodes:
                                next_mid += 1
                                pm = 0.5 * (xyz[g[a]] + xyz[g[b]])
                                model.add_grid(next_mid, [r4(v) for v in pm])
                                mid_nodes[key] = next_mid
                            nodes.append(mid_nodes[key])
                    eid += 1
                    model.add_ctetra(eid, pid, nodes)
                    elems.append(eid)
    return {"nid": nid, "eid_end": eid, "elems": elems}


def _rot(axis: str, deg: float) -> np.ndarray:
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    if axis == "x":
        return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
    if axis == "y":
        return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def add_coords(model: BDF, cid_r: int, cid_c: int, cid_nested: int,
               exact8: bool) -> None:
    """Rotated CORD2R, a CORD2C (RID 0) and a CORD2C nested in the CORD2R.

    exact8=False keeps full double precision in the A/B/C points.
    """
    rot = _rot("z", 30.0) @ _rot("y", 20.0) @ _rot("x", 10.0)
    origin = np.array([1.5, -0.5, 0.25])
    a = origin
    b = origin + rot[:, 2]                 # on the local z axis
    c = origin + rot[:, 0] + 0.5 * rot[:, 2]  # in the local x-z plane
    if exact8:
        a, b, c = ([r4(v) for v in p] for p in (a, b, c))
    model.add_cord2r(cid_r, list(map(float, a)), list(map(float, b)), list(map(float, c)))
    # cylindrical system: axis along basic Y, origin at (0, 0, -1)
    model.add_cord2c(cid_c, [0.0, 0.0, -1.0], [0.0, 1.0, -1.0], [1.0, 0.0, -1.0])
    # cylindrical system defined inside the rotated rectangular one
    model.add_cord2c(cid_nested, [0.2, 0.1, 0.0], [0.2, 0.1, 1.0], [1.2, 0.3, 0.0],
                     rid=cid_r)


def add_conm2_coords_part(model: BDF, nid0: int, eid0: int, pid: int, mid: int,
                          cid_r: int, cid_c: int, cid_nested: int) -> dict:
    """Cylindrical CQUAD4 panel with CP != 0 grids and CONM2s in several CIDs."""
    model.add_mat1(mid, 7.0e10, None, 0.33, rho=2800.0)
    model.add_pshell(pid, mid1=mid, t=0.003, mid2=mid, mid3=mid, nsm=0.8)
    nid = {}
    # panel in CORD2C cid_c: r = 1.2, theta 0..60 deg, z = 0..0.6
    for j in range(4):
        for i in range(7):
            n = nid0 + 10 * j + i + 1
            model.add_grid(n, [1.2, 10.0 * i, 0.2 * j], cp=cid_c)
            nid["cyl", i, j] = n
    # small flat patch in the rotated CORD2R
    for j in range(3):
        for i in range(3):
            n = nid0 + 100 + 10 * j + i + 1
            model.add_grid(n, [0.25 * i, 0.2 * j + 0.01 * i, 0.0], cp=cid_r)
            nid["rect", i, j] = n
    # grids in the nested cylindrical system (CP -> CORD2C -> CORD2R -> basic)
    for i in range(3):
        n = nid0 + 200 + i + 1
        model.add_grid(n, [0.5, 25.0 * i, 0.1 * i], cp=cid_nested, cd=cid_r)
        nid["nest", i] = n
    eid = eid0
    for j in range(3):
        for i in range(6):
            eid += 1
            model.add_cquad4(eid, pid, [nid["cyl", i, j], nid["cyl", i + 1, j],
                                        nid["cyl", i + 1, j + 1], nid["cyl", i, j + 1]])
    for j in range(2):
        for i in range(2):
            eid += 1
            model.add_cquad4(eid, pid, [nid["rect", i, j], nid["rect", i + 1, j],
                                        nid["rect", i + 1, j + 1], nid["rect", i, j + 1]])
    eid += 1
    model.add_ctria3(eid, pid, [nid["nest", 0], nid["nest", 1], nid["nest", 2]])
    # CONM2s (I = [I11, I21, I22, I31, I32, I33])
    m = eid0 + 900
    model.add_conm2(m + 1, nid["rect", 0, 0], 12.5, cid=0, X=[0.1, -0.2, 0.05],
                    I=[0.8, 0.0, 1.1, 0.0, 0.0, 0.6])
    model.add_conm2(m + 2, nid["cyl", 3, 1], 4.0, cid=-1, X=[0.4, 0.9, -0.3],
                    I=[0.2, 0.0, 0.25, 0.0, 0.0, 0.3])
    model.add_conm2(m + 3, nid["rect", 2, 2], 7.5, cid=cid_r, X=[0.3, 0.1, -0.2])
    # grid at theta = 0 of cid_c and X2 = 0: pyNastran == Nastran here
    model.add_conm2(m + 4, nid["cyl", 0, 2], 3.25, cid=cid_c, X=[0.15, 0.0, 0.05])
    model.add_conm2(m + 5, nid["cyl", 5, 3], 2.0, cid=0, X=[-0.05, 0.0, 0.12],
                    I=[0.05, 0.0, 0.07, 0.0, 0.0, 0.09])
    model.add_conm2(m + 6, nid["nest", 1], 1.5)
    return {"nid": nid, "eid_end": eid, "conm2": list(range(m + 1, m + 7))}


# --------------------------------------------------------------------------
# models
# --------------------------------------------------------------------------
def model_plate_pshell() -> BDF:
    model = new_model("plate_pshell: distorted CQUAD4/CTRIA3, PSHELL + NSM")
    model.add_mat1(1, 7.1e10, None, 0.33, rho=2700.0)
    part = add_shell_plate(model, 0, 0, 1, 1)
    nid = part["nid"]
    model.add_spc1(1, "123456", [nid[i, 0] for i in range(8)])
    model.add_force(2, nid[7, 5], 100.0, [0.0, 0.0, 1.0])
    return model


def model_pcomp_plate() -> BDF:
    model = new_model("pcomp_plate: angle-ply PCOMP, LAM=SYM, MAT8")
    model.add_cord2r(5, [0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.866, 0.5, 0.0])
    part = add_pcomp_plate(model, 0, 0, 10, 2, mcid=5)
    nid = part["nid"]
    model.add_spc1(1, "123456", [nid[0, j] for j in range(5)])
    model.add_force(2, nid[6, 4], 50.0, [0.0, 0.0, -1.0])
    return model


def model_solid_hexa() -> BDF:
    model = new_model("solid_hexa: distorted CHEXA + CPENTA, PARAM WTMASS")
    model.add_param("WTMASS", [0.00259])
    # inch / lbf units: densities in lbf/in^3
    part = add_hexa_penta_block(model, 0, 0, 1, 1, rho_hexa=0.101, rho_penta=0.283)
    nid = part["nid"]
    model.add_spc1(1, "123", [nid[0, j, k] for j in range(4) for k in range(3)])
    model.add_force(2, nid[4, 3, 2], 1000.0, [0.0, 1.0, 0.0])
    return model


def model_solid_tetra() -> BDF:
    model = new_model("solid_tetra: CTETRA 4-node and 10-node")
    a = add_tetra_block(model, 0, 0, 1, 1, n=(4, 3, 3), seed=4)
    b = add_tetra_block(model, 10000, 1000, 2, 2, origin=(2.0, 0.0, 0.0), n=(3, 3, 2),
                        seed=5, tet10=True, rho=4430.0)
    fixed = [a["nid"][0, j, k] for j in range(3) for k in range(3)]
    fixed += [b["nid"][0, j, k] for j in range(3) for k in range(2)]
    model.add_spc1(1, "123", fixed)
    model.add_force(2, a["nid"][3, 2, 2], 500.0, [0.0, 0.0, -1.0])
    return model


def model_conm2_coords(exact8: bool = False) -> BDF:
    model = new_model("conm2_coords: CONM2 offsets/CID, CORD2R, CORD2C, CP != 0")
    add_coords(model, 10, 20, 30, exact8=exact8)
    part = add_conm2_coords_part(model, 0, 0, 1, 1, 10, 20, 30)
    nid = part["nid"]
    model.add_spc1(1, "123456", [nid["cyl", i, 0] for i in range(7)])
    model.add_force(2, nid["cyl", 6, 3], 10.0, [1.0, 0.0, 0.0], cid=20)
    return model


def model_mixed() -> BDF:
    model = new_model("mixed: shells, composites, solids, masses, RBE2/RBE3, CELAS")
    model.add_mat1(1, 7.1e10, None, 0.33, rho=2700.0)
    plate = add_shell_plate(model, 0, 0, 1, 1, variable_thickness=True)
    model.add_cord2r(5, [0.0, 0.0, 0.0], [0.0, 0.0, 1.0], [0.866, 0.5, 0.0])
    comp = add_pcomp_plate(model, 1000, 1000, 10, 2, mcid=5, origin=(0.0, 1.5, 0.0),
                           nx=5, ny=4)
    block = add_hexa_penta_block(model, 2000, 2000, 20, 20, origin=(0.3, 0.2, 0.5),
                                 nx=4, ny=3, nz=2)
    tet4 = add_tetra_block(model, 6000, 3000, 30, 30, origin=(2.3, 0.0, 0.0),
                           n=(3, 3, 2), seed=6)
    tet10 = add_tetra_block(model, 7000, 4000, 31, 31, origin=(2.3, 1.2, 0.0),
                            n=(2, 2, 2), seed=7, tet10=True, rho=4430.0)
    add_coords(model, 10, 20, 30, exact8=True)
    masses = add_conm2_coords_part(model, 8000, 5000, 40, 40, 10, 20, 30)

    # RBE2: block bottom corner grids slaved to a plate grid
    bn = block["nid"]
    model.add_rbe2(9001, plate["nid"][3, 2], "123456",
                   [bn[0, 0, 0], bn[1, 0, 0], bn[0, 1, 0], bn[1, 1, 0]])
    # RBE3: reference grid = a CONM2 grid, weighted average of plate grids
    pn = plate["nid"]
    model.add_rbe3(9002, masses["nid"]["rect", 0, 0], "123456",
                   weights=[1.0, 2.5],
                   comps=["123", "123"],
                   Gijs=[[pn[6, 4], pn[7, 4]], [pn[6, 5], pn[7, 5]]])
    # springs: CELAS1 through PELAS, CELAS2 with K on the card
    model.add_pelas(50, 1.0e6, ge=0.01)
    model.add_celas1(9101, 50, [pn[0, 5], comp["nid"][0, 0]], 3, 3)
    model.add_celas1(9102, 50, [pn[7, 5], tet4["nid"][0, 0, 0]], 1, 1)
    model.add_celas2(9103, 2.5e5, [tet10["nid"][1, 1, 1], 0], 2, 0)   # grounded
    model.add_celas2(9104, 7.5e5, [pn[4, 5], comp["nid"][2, 0]], 6, 6, ge=0.02)

    model.add_spc1(1, "123456", [pn[i, 0] for i in range(8)])
    model.add_spc1(1, "123", [tet4["nid"][0, j, k] for j in range(3) for k in range(2)])
    model.add_force(2, pn[7, 5], 100.0, [0.0, 0.0, 1.0])
    model.add_force(2, masses["nid"]["cyl", 6, 3], 10.0, [1.0, 0.0, 0.0], cid=20)
    return model


# --------------------------------------------------------------------------
# regular-geometry models: pyNastran's mass formulas are exact on them
# (flat parallelogram quads, triangles, right-prism hexas/wedges, tetras,
# CONM2 with CID 0/-1 and diagonal inertia), so paraflex must agree to 1e-10
# --------------------------------------------------------------------------
def add_parallelogram_grid(model: BDF, nid0: int, nx: int, ny: int, dx: float, dy: float,
                           shear: float, origin=(0.0, 0.0, 0.0)) -> dict:
    """Flat grid of parallelograms: x = i dx + j shear, y = j dy."""
    nid = {}
    for j in range(ny):
        for i in range(nx):
            n = nid0 + 100 * (j + 1) + (i + 1)
            model.add_grid(n, [r4(origin[0] + dx * i + shear * j), r4(origin[1] + dy * j), r4(origin[2])])
            nid[i, j] = n
    return nid


def model_plate_regular() -> BDF:
    model = new_model("plate_regular: flat parallelogram CQUAD4 + CTRIA3, PSHELL + NSM")
    model.add_mat1(1, 7.1e10, None, 0.33, rho=2700.0)
    model.add_mat1(2, 2.1e11, None, 0.29, rho=7850.0)
    model.add_pshell(1, mid1=1, t=0.002, mid2=1, mid3=1, nsm=0.35)
    model.add_pshell(2, mid2=2, t=0.0015, nsm=0.1)            # MID1 blank: rho of MID2
    nid = add_parallelogram_grid(model, 0, 7, 5, 0.25, 0.2, 0.05)
    eid = 0
    for j in range(4):
        for i in range(6):
            n1, n2, n3, n4 = nid[i, j], nid[i + 1, j], nid[i + 1, j + 1], nid[i, j + 1]
            if i < 4:
                eid += 1
                model.add_cquad4(eid, 1, [n1, n2, n3, n4], theta_mcid=15.0 * (i % 2))
            else:
                eid += 1
                model.add_ctria3(eid, 2, [n1, n2, n3])
                eid += 1
                model.add_ctria3(eid, 1, [n1, n3, n4])
    model.add_spc1(1, "123456", [nid[0, j] for j in range(5)])
    return model


def model_pcomp_regular() -> BDF:
    model = new_model("pcomp_regular: angle-ply PCOMP and LAM=SYM on a parallelogram mesh")
    model.add_mat8(2, 1.4e11, 9.0e9, 0.3, g12=5.0e9, g1z=4.5e9, g2z=3.0e9, rho=1600.0)
    model.add_mat8(3, 4.5e10, 1.2e10, 0.28, g12=4.5e9, g1z=4.0e9, g2z=3.5e9, rho=1950.0)
    model.add_pcomp(10, mids=[2, 2, 3, 2, 2, 3, 2, 2],
                    thicknesses=[1.25e-4, 1.25e-4, 2.0e-4, 1.25e-4, 1.25e-4, 2.0e-4, 1.25e-4, 1.25e-4],
                    thetas=[30.0, -30.0, 30.0, -30.0, -30.0, 30.0, -30.0, 30.0], nsm=0.12)
    model.add_pcomp(11, mids=[2, 3, 2, 2], thicknesses=[1.5e-4, 2.5e-4, 1.5e-4, 1.0e-4],
                    thetas=[45.0, -45.0, 45.0, -45.0], nsm=0.05, lam="SYM")
    nid = add_parallelogram_grid(model, 0, 7, 5, 0.3, 0.25, -0.06, origin=(0.1, 0.2, 0.3))
    eid = 0
    for j in range(4):
        for i in range(6):
            n1, n2, n3, n4 = nid[i, j], nid[i + 1, j], nid[i + 1, j + 1], nid[i, j + 1]
            pid = 10 if i < 3 else 11
            eid += 1
            if (i, j) == (5, 3):
                model.add_ctria3(eid, pid, [n1, n2, n4])
                eid += 1
                model.add_ctria3(eid, pid, [n2, n3, n4])
            else:
                model.add_cquad4(eid, pid, [n1, n2, n3, n4])
    model.add_spc1(1, "123456", [nid[0, j] for j in range(5)])
    return model


def model_solid_regular() -> BDF:
    model = new_model("solid_regular: box CHEXA + right-prism CPENTA, PARAM WTMASS")
    model.add_param("WTMASS", [0.5])
    model.add_mat1(1, 7.0e10, None, 0.33, rho=2700.0)
    model.add_mat1(2, 2.1e11, None, 0.29, rho=7850.0)
    model.add_psolid(1, 1)
    model.add_psolid(2, 2)
    xs, ys, zs = [0.0, 0.5, 0.8, 1.4, 1.7], [0.0, 0.4, 0.9, 1.2], [0.0, 0.3, 0.75]
    nid = {}
    for k, z in enumerate(zs):
        for j, y in enumerate(ys):
            for i, x in enumerate(xs):
                n = 1000 * k + 20 * j + i + 1
                model.add_grid(n, [x, y, z])
                nid[i, j, k] = n
    eid = 0
    for k in range(len(zs) - 1):
        for j in range(len(ys) - 1):
            for i in range(len(xs) - 1):
                a, b = nid[i, j, k], nid[i + 1, j, k]
                c, d = nid[i + 1, j + 1, k], nid[i, j + 1, k]
                e, f = nid[i, j, k + 1], nid[i + 1, j, k + 1]
                g, h = nid[i + 1, j + 1, k + 1], nid[i, j + 1, k + 1]
                eid += 1
                if i == len(xs) - 2:
                    model.add_cpenta(eid, 2, [a, b, c, e, f, g])
                    eid += 1
                    model.add_cpenta(eid, 2, [a, c, d, e, g, h])
                else:
                    model.add_chexa(eid, 1, [a, b, c, d, e, f, g, h])
    model.add_spc1(1, "123", [nid[0, j, k] for j in range(len(ys)) for k in range(len(zs))])
    return model


def model_tetra_regular() -> BDF:
    model = new_model("tetra_regular: CTETRA 4-node and 10-node blocks", with_spc=False)
    add_tetra_block(model, 0, 0, 1, 1, n=(3, 3, 2), seed=11)
    add_tetra_block(model, 10000, 1000, 2, 2, origin=(1.5, 0.0, 0.0), n=(3, 2, 2), seed=12,
                    tet10=True, rho=4430.0)
    return model


def model_conm2_regular() -> BDF:
    model = new_model("conm2_regular: CONM2 offsets with CID 0, -1 and a rotated CORD2R", with_spc=False)
    rot = _rot("z", 30.0) @ _rot("y", 20.0) @ _rot("x", 10.0)
    origin = np.array([1.5, -0.5, 0.25])
    model.add_cord2r(10, list(map(float, origin)), list(map(float, origin + rot[:, 2])),
                     list(map(float, origin + rot[:, 0] + 0.5 * rot[:, 2])))
    model.add_mat1(1, 7.0e10, None, 0.33, rho=2800.0)
    model.add_pshell(1, mid1=1, t=0.003, nsm=0.8)
    nid = add_parallelogram_grid(model, 0, 3, 3, 0.4, 0.3, 0.1)
    model.add_grid(901, [0.25, 0.2, 0.0], cp=10)
    model.add_grid(902, [-0.3, 0.1, 0.4], cp=10)
    eid = 0
    for j in range(2):
        for i in range(2):
            eid += 1
            model.add_cquad4(eid, 1, [nid[i, j], nid[i + 1, j], nid[i + 1, j + 1], nid[i, j + 1]])
    model.add_conm2(101, nid[0, 0], 12.5, cid=0, X=[0.1, -0.2, 0.05], I=[0.8, 0.0, 1.1, 0.0, 0.0, 0.6])
    model.add_conm2(102, nid[2, 1], 4.0, cid=-1, X=[0.4, 0.9, -0.3], I=[0.2, 0.0, 0.25, 0.0, 0.0, 0.3])
    model.add_conm2(103, nid[2, 2], 2.0, cid=0, X=[-0.05, 0.0, 0.12], I=[0.05, 0.0, 0.07, 0.0, 0.0, 0.09])
    # rotated CORD2R: offset rotated; diagonal inertia in the CID axes (pyNastran drops it,
    # tests/conformance_mass.rs adds the rotated tensor T J T^T to the reference)
    model.add_conm2(104, 901, 7.5, cid=10, X=[0.3, 0.1, -0.2], I=[0.4, 0.0, 0.9, 0.0, 0.0, 1.3])
    model.add_conm2(105, 902, 1.5, cid=10, X=[0.0, 0.0, 0.1])
    return model


MODELS = {
    "plate_pshell": model_plate_pshell,
    "pcomp_plate": model_pcomp_plate,
    "solid_hexa": model_solid_hexa,
    "solid_tetra": model_solid_tetra,
    "conm2_coords": model_conm2_coords,
    "mixed": model_mixed,
    "plate_regular": model_plate_regular,
    "pcomp_regular": model_pcomp_regular,
    "solid_regular": model_solid_regular,
    "tetra_regular": model_tetra_regular,
    "conm2_regular": model_conm2_regular,
}


# --------------------------------------------------------------------------
# writers
# --------------------------------------------------------------------------
def write_fixed(model: BDF, size: int) -> str:
    buf = io.StringIO()
    model.write_bdf(buf, size=size, close=False, enddata=True)
    return buf.getvalue()


def small_to_free(text: str) -> str:
    """Convert a small-field deck (as written by pyNastran) to free field.

    Lines up to and including BEGIN BULK, comments and ENDDATA are copied.
    Each bulk card is split into fields with pyNastran's ``to_fields`` and
    re-emitted as ``NAME,f2..f9`` plus ``+,f10..f17`` continuation lines (free form of
    :func:`paraflex_tools.cards.card`).
    """
    out: list[str] = []
    lines = text.splitlines()
    ibulk = next(i for i, line in enumerate(lines) if line.upper().startswith("BEGIN BULK"))
    out.extend(lines[: ibulk + 1])
    card: list[str] = []

    def flush() -> None:
        if not card:
            return
        name = card[0][:8].strip()
        fields = [f.strip() for f in to_fields(card, name)]
        assert all(len(f) <= 8 for f in fields), fields
        while len(fields) > 1 and fields[-1] == "":
            fields.pop()
        out.append(free_card(name, *fields[1:]).removesuffix("\n"))
        card.clear()

    for line in lines[ibulk + 1:]:
        if line.startswith("$") or not line.strip():
            flush()
            out.append(line)
        elif line.upper().startswith("ENDDATA"):
            flush()
            out.append(line)
        elif line[0] in " +*":
            assert line[0] != "*", "free conversion expects a small-field deck"
            card.append(line)
        else:
            flush()
            card.append(line)
    flush()
    return "\n".join(out) + "\n"


def main() -> None:
    OUT_DIR.mkdir(parents=True, exist_ok=True)
    for name, build in MODELS.items():
        model = build()
        small = write_fixed(model, 8)
        large = write_fixed(model, 16)
        free = small_to_free(small)
        for kind, text in (("small", small), ("large", large), ("free", free)):
            path = OUT_DIR / f"{name}_{kind}.bdf"
            path.write_text(text)
            print(f"wrote {path.relative_to(REPO)} ({len(model.nodes)} grids, "
                  f"{len(model.elements) + len(model.masses)} elements)")


if __name__ == "__main__":
    main()
