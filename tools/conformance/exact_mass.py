"""Independent exact mass properties of the distorted conformance decks.

For every deck in ``DECKS`` (all three formats of plate_pshell, pcomp_plate,
solid_hexa and mixed) this writes ``reference/conformance/<stem>.exact.json``::

    {"provenance": "...", "mass": M, "cg": [x, y, z],
     "inertia_cg": [[Ixx, -Ixy, -Ixz], [-Ixy, Iyy, -Iyz], [-Ixz, -Iyz, Izz]]}

with paraflex's *exact* convention (src/model/mass.rs module documentation),
computed here independently of the Rust code:

* pyNastran 1.4.1 is used only to read the cards, to give grid positions in
  basic (``GRID.get_position()``) and the axes/origin of the CORD2x systems.
  pyNastran's ``mass_properties`` is NOT used (it is approximate on these
  decks, see PYNASTRAN_MASS.md).
* Every element is written as a map x(u, v[, w]) from the unit square/cube
  and integrated with a *composite* tensor Gauss-Legendre rule (the unit
  interval split into S equal panels, n points per panel per direction, points
  from numpy.polynomial.legendre.leggauss):
    - CQUAD4: bilinear surface, dm = mu(u, v) |x_u x x_v| du dv with mu the
      bilinear interpolant of the corner masses per area (NSM + rho t_i);
    - CTRIA3: the same routine on the collapsed quad (G1, G2, G3, G3), whose
      map is the Duffy map of the flat triangle (mu at the 4th corner = mu_3
      gives exactly the linear interpolant), instead of closed-form moments;
    - CHEXA: trilinear map, dm = rho det(dx/d(u,v,w));
    - CPENTA: collapsed hexa (G1 G2 G3 G3 / G4 G5 G6 G6);
    - CTETRA 4: collapsed hexa (G1 G2 G3 G3 / G4 G4 G4 G4);
    - CTETRA 10: quadratic tetra shape functions of barycentric coordinates
      composed with a Duffy map collapsing towards G1, Jacobian by the chain
      rule (mid-side grids used as given).
  Mass m = int dm and lumping point int x dm / m; signed volumes (an inverted
  solid would show as negative mass and is reported).
* Mass per area: PSHELL NSM + rho(MID1, or MID2 if MID1 blank) t_i with
  t_i = T_i * T (TFLAG=1), T_i (TFLAG=0), T (blank T_i); PCOMP
  k * sum(rho_i t_i) + NSM over the plies on the card (k = 2 for LAM=SYM,
  NSM not doubled; element T_i ignored). Solids rho * dV (PSOLID's MAT1).
* CONM2: point mass at G + X (CID 0), X (CID -1), G + T X (CID > 0, T the
  local Cartesian axes of CID at the grid as columns: i, j, k for CORD2R,
  e_r, e_theta, e_z for CORD2C), plus T J T^T with
  J = [[I11, -I21, -I31], [-I21, I22, -I32], [-I31, -I32, I33]].
* Totals with math.fsum; cg = sum m x / sum m (not scaled by WTMASS);
  inertia_cg = WTMASS * (sum m (|d|^2 1 - d d^T) + sum J), d = x - cg (two
  passes, directly about the cg), mass = WTMASS * sum m.

Convergence: each deck is evaluated with two different composite rules
(LOW and HIGH below); the relative change (norm-wise, per quantity) is printed
and must be < 1e-13, otherwise the script exits 1.  The HIGH result is written.

Run from the repository root:  .venv/bin/python tools/conformance/exact_mass.py
"""
from __future__ import annotations

import json
import math
import sys
import warnings
from pathlib import Path

import numpy as np
from numpy.polynomial.legendre import leggauss
from pyNastran.bdf.bdf import BDF

REPO = Path(__file__).resolve().parents[2]
DECK_DIR = REPO / "decks" / "conformance"
REF_DIR = REPO / "reference" / "conformance"
MODELS = ("plate_pshell", "pcomp_plate", "solid_hexa", "mixed")
DECKS = [f"{m}_{k}" for m in MODELS for k in ("small", "large", "free")]

# (panels per direction, Gauss points per panel per direction)
SHELL_LOW, SHELL_HIGH = (4, 12), (8, 20)
SOLID_LOW, SOLID_HIGH = (1, 5), (3, 7)
CONVERGENCE_LIMIT = 1e-13


# ----------------------------------------------------------------------------
# composite Gauss rules on [0, 1]^d
# ----------------------------------------------------------------------------
def rule_1d(panels: int, n: int) -> tuple[np.ndarray, np.ndarray]:
    x, w = leggauss(n)
    pts, wts = [], []
    h = 1.0 / panels
    for k in range(panels):
        a = k * h
        pts.append(a + 0.5 * h * (x + 1.0))
        wts.append(0.5 * h * w)
    return np.concatenate(pts), np.concatenate(wts)


def rule_nd(dim: int, panels: int, n: int) -> tuple[np.ndarray, np.ndarray]:
    x, w = rule_1d(panels, n)
    grids = np.meshgrid(*([x] * dim), indexing="ij")
    wgrids = np.meshgrid(*([w] * dim), indexing="ij")
    pts = np.stack([g.ravel() for g in grids], axis=1)
    wts = np.prod(np.stack([g.ravel() for g in wgrids], axis=1), axis=1)
    return pts, wts


# ----------------------------------------------------------------------------
# element integrals: returns (m, first moment int x dm)
# ----------------------------------------------------------------------------
def shell_quad(p: np.ndarray, mu: np.ndarray, rule) -> tuple[float, np.ndarray]:
    """Bilinear surface through p[0..3] (corner order), mu bilinear between the corners."""
    uv, w = rule
    u, v = uv[:, 0:1], uv[:, 1:2]
    n = np.hstack([(1 - u) * (1 - v), u * (1 - v), u * v, (1 - u) * v])
    x = n @ p
    xu = (1 - v) * (p[1] - p[0]) + v * (p[2] - p[3])
    xv = (1 - u) * (p[3] - p[0]) + u * (p[2] - p[1])
    da = np.linalg.norm(np.cross(xu, xv), axis=1)
    dm = w * da * (n @ mu)
    return math.fsum(dm), np.array([math.fsum(dm * x[:, k]) for k in range(3)])


def solid_trilinear(p8: np.ndarray, rule) -> tuple[float, np.ndarray]:
    """Trilinear map of the unit cube through p8 (hexa corner order); signed volume."""
    q, w = rule
    u, v, t = q[:, 0:1], q[:, 1:2], q[:, 2:3]
    a, b, c = 1 - u, 1 - v, 1 - t
    n = np.hstack([a * b * c, u * b * c, u * v * c, a * v * c, a * b * t, u * b * t, u * v * t, a * v * t])
    dnu = np.hstack([-b * c, b * c, v * c, -v * c, -b * t, b * t, v * t, -v * t])
    dnv = np.hstack([-a * c, -u * c, u * c, a * c, -a * t, -u * t, u * t, a * t])
    dnt = np.hstack([-a * b, -u * b, -u * v, -a * v, a * b, u * b, u * v, a * v])
    x = n @ p8
    jac = np.stack([dnu @ p8, dnv @ p8, dnt @ p8], axis=1)  # rows: x_u, x_v, x_t
    det = np.linalg.det(jac)
    dv = w * det
    return math.fsum(dv), np.array([math.fsum(dv * x[:, k]) for k in range(3)])


def solid_tetra10(p10: np.ndarray, rule, order=(1, 2, 3, 0)) -> tuple[float, np.ndarray]:
    """Quadratic tetra (Nastran G1..G4, G5..G10 on edges 12, 23, 31, 14, 24, 34, mid-side grids
    used as given) on the unit cube through a Duffy map of the barycentric coordinates: with
    order = (a, b, c, d), L_d = t, L_c = v (1 - t), L_b = u (1 - v)(1 - t), L_a = the rest
    (default: collapse towards G1, then G4, then G3). The volume element is det of
    d x / d(u, v, t) by the chain rule (it contains the Duffy Jacobian (1 - v)(1 - t)^2), times
    the orientation sign of that Duffy map (+1 for the reference tet), so volumes are signed as
    Nastran's (positive when G4 is on the side of (G2 - G1) x (G3 - G1)).
    """
    q, w = rule
    u, v, t = q[:, 0], q[:, 1], q[:, 2]
    a, b, c, d = order
    lam = np.zeros((len(u), 4))
    dl = np.zeros((len(u), 4, 3))  # [point, L index, d/d(u, v, t)]
    lam[:, d] = t
    dl[:, d, 2] = 1.0
    lam[:, c] = v * (1 - t)
    dl[:, c, 1] = 1 - t
    dl[:, c, 2] = -v
    lam[:, b] = u * (1 - v) * (1 - t)
    dl[:, b, 0] = (1 - v) * (1 - t)
    dl[:, b, 1] = -u * (1 - t)
    dl[:, b, 2] = -u * (1 - v)
    lam[:, a] = 1 - lam[:, b] - lam[:, c] - lam[:, d]
    dl[:, a, :] = -(dl[:, b, :] + dl[:, c, :] + dl[:, d, :])
    # orientation of the Duffy map: sign of det(dL_{1,2,3}/d(u,v,t)) (x = G1 + sum L_i (G_i - G1)
    # for a straight tet, so that determinant times 6V is det(dx/d(u,v,t)))
    sign = np.sign(np.linalg.det(dl[:, 1:4, :]))
    assert np.all(sign == sign[0]) and sign[0] != 0, "degenerate Duffy map"
    sign = float(sign[0])
    edges = [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]
    n = [lam[:, k] * (2 * lam[:, k] - 1) for k in range(4)]
    dn = [(4 * lam[:, k] - 1)[:, None] * dl[:, k, :] for k in range(4)]
    for a, b in edges:
        n.append(4 * lam[:, a] * lam[:, b])
        dn.append(4 * (lam[:, a][:, None] * dl[:, b, :] + lam[:, b][:, None] * dl[:, a, :]))
    n = np.stack(n, axis=1)  # (npts, 10)
    dn = np.stack(dn, axis=1)  # (npts, 10, 3)
    x = n @ p10
    jac = np.einsum("pic,ij->pcj", dn, p10)  # rows d x / d(u, v, t)
    det = sign * np.linalg.det(jac)
    dv = w * det
    return math.fsum(dv), np.array([math.fsum(dv * x[:, k]) for k in range(3)])


# ----------------------------------------------------------------------------
# properties
# ----------------------------------------------------------------------------
def rho(model: BDF, mid) -> float:
    if mid is None or mid == 0:
        return 0.0
    r = model.materials[mid].rho
    return 0.0 if r is None else float(r)


def corner_mass_per_area(model: BDF, elem, ncorner: int) -> np.ndarray:
    prop = model.properties[elem.pid]
    if prop.type == "PSHELL":
        mid = prop.mid1 if prop.mid1 not in (None, 0) else prop.mid2
        r = rho(model, mid)
        tnom = float(prop.t)
        ts = [elem.T1, elem.T2, elem.T3] + ([elem.T4] if ncorner == 4 else [])
        out = []
        for ti in ts:
            if ti is None:
                t = tnom
            elif elem.tflag == 1:
                t = ti * tnom
            else:
                t = ti
            out.append(prop.nsm + r * t)
        return np.array(out, dtype=float)
    if prop.type == "PCOMP":
        s = math.fsum(rho(model, m) * t for m, t in zip(prop.mids, prop.thicknesses))
        k = 2.0 if prop.lam == "SYM" else 1.0
        return np.full(ncorner, k * s + prop.nsm)
    raise ValueError(f"{elem.type} {elem.eid}: unsupported property {prop.type}")


def local_axes(coord, grid: np.ndarray) -> np.ndarray:
    """Local Cartesian axes of a CORD2R/CORD2C at a point (basic), as columns."""
    i, j, k = (np.asarray(a, dtype=float) for a in (coord.i, coord.j, coord.k))
    if coord.type in ("CORD2R", "CORD1R"):
        return np.column_stack([i, j, k])
    if coord.type in ("CORD2C", "CORD1C"):
        d = grid - np.asarray(coord.origin, dtype=float)
        theta = math.atan2(float(d @ j), float(d @ i))
        er = math.cos(theta) * i + math.sin(theta) * j
        et = -math.sin(theta) * i + math.cos(theta) * j
        return np.column_stack([er, et, k])
    raise ValueError(f"coordinate system {coord.cid} of type {coord.type} not supported")


# ----------------------------------------------------------------------------
# deck
# ----------------------------------------------------------------------------
def read_deck(path: Path) -> BDF:
    model = BDF(debug=None, log=None)
    model.log.level = "error"
    model.read_bdf(str(path), xref=True, punch=None)
    return model


def mass_points(model: BDF, shell_rule, solid_rule):
    """List of (eid, m, point, J or None) in basic."""
    pos = {nid: np.asarray(node.get_position(), dtype=float) for nid, node in model.nodes.items()}
    out = []
    for eid, elem in model.elements.items():
        t = elem.type
        if t in ("CELAS1", "CELAS2", "CELAS3", "CELAS4"):
            continue
        nids = list(elem.node_ids)
        p = np.array([pos[n] for n in nids])
        if t == "CQUAD4":
            m, s = shell_quad(p, corner_mass_per_area(model, elem, 4), shell_rule)
        elif t == "CTRIA3":
            mu = corner_mass_per_area(model, elem, 3)
            m, s = shell_quad(p[[0, 1, 2, 2]], mu[[0, 1, 2, 2]], shell_rule)
        elif t in ("CHEXA", "CPENTA", "CTETRA"):
            prop = model.properties[elem.pid]
            assert prop.type == "PSOLID", (eid, prop.type)
            r = rho(model, prop.mid)
            if t == "CHEXA" and len(nids) == 8:
                v, s = solid_trilinear(p, solid_rule)
            elif t == "CPENTA" and len(nids) == 6:
                v, s = solid_trilinear(p[[0, 1, 2, 2, 3, 4, 5, 5]], solid_rule)
            elif t == "CTETRA" and len(nids) == 4:
                v, s = solid_trilinear(p[[0, 1, 2, 2, 3, 3, 3, 3]], solid_rule)
            elif t == "CTETRA" and len(nids) == 10:
                v, s = solid_tetra10(p, solid_rule)
            else:
                raise ValueError(f"{t} {eid} with {len(nids)} grids not supported")
            if v <= 0:
                print(f"  WARNING {t} {eid}: volume {v} <= 0", file=sys.stderr)
            m, s = r * v, r * s
        else:
            raise ValueError(f"element type {t} not supported")
        out.append((eid, m, s / m if m != 0 else p.mean(axis=0), None))
    for eid, c in model.masses.items():
        if c.type != "CONM2":
            raise ValueError(f"mass type {c.type} not supported")
        i11, i21, i22, i31, i32, i33 = (float(x) for x in c.I)
        jl = np.array([[i11, -i21, -i31], [-i21, i22, -i32], [-i31, -i32, i33]])
        x = np.asarray(c.X, dtype=float)
        cid = c.Cid()
        g = pos[c.Nid()] if cid != -1 else None
        if cid == -1:
            point, tm = x, np.eye(3)
        elif cid == 0:
            point, tm = g + x, np.eye(3)
        else:
            tm = local_axes(model.coords[cid], g)
            point = g + tm @ x
        jb = tm @ jl @ tm.T
        out.append((eid, float(c.mass), point, jb if np.any(jl != 0) else None))
    return out


def totals(model: BDF, points) -> dict:
    wt = float(model.params["WTMASS"].values[0]) if "WTMASS" in model.params else 1.0
    total = math.fsum(m for _, m, _, _ in points)
    cg = np.array([math.fsum(m * x[k] for _, m, x, _ in points) for k in range(3)]) / total
    terms = [[[] for _ in range(3)] for _ in range(3)]
    for _, m, x, jb in points:
        d = x - cg
        d2 = float(d @ d)
        for a in range(3):
            for b in range(3):
                terms[a][b].append(m * ((d2 if a == b else 0.0) - d[a] * d[b]))
                if jb is not None:
                    terms[a][b].append(jb[a][b])
    inertia = [[wt * math.fsum(terms[a][b]) for b in range(3)] for a in range(3)]
    return {"mass": wt * total, "cg": [float(v) for v in cg], "inertia_cg": inertia, "wtmass": wt}


def rel_change(a: dict, b: dict) -> list[float]:
    dm = abs(a["mass"] - b["mass"]) / abs(b["mass"])
    dcg = np.linalg.norm(np.subtract(a["cg"], b["cg"])) / np.linalg.norm(b["cg"])
    di = np.linalg.norm(np.subtract(a["inertia_cg"], b["inertia_cg"])) / np.linalg.norm(b["inertia_cg"])
    return [float(dm), float(dcg), float(di)]


def provenance(change: float) -> str:
    sl, sh = SHELL_LOW, SHELL_HIGH
    ol, oh = SOLID_LOW, SOLID_HIGH
    return (
        "paraflex exact mass convention (src/model/mass.rs docs) by independent numpy integration, "
        "tools/conformance/exact_mass.py; pyNastran 1.4.1 used only to read the cards, grid "
        "positions in basic and CORD2x axes. Element mass lumped at its exact centroid "
        "int x dm / m: CQUAD4 bilinear surface, dm = mu |x_u x x_v| du dv, mu bilinear in the corner "
        "mass per area (PSHELL NSM + rho(MID1|MID2) t_i, TFLAG=1 ratios; PCOMP k*sum(rho t) + NSM, "
        "k=2 for SYM); CTRIA3 as the collapsed (Duffy) quad G1 G2 G3 G3; CHEXA trilinear det J, "
        "CPENTA and CTETRA4 as collapsed hexas, CTETRA10 quadratic via a Duffy map; composite "
        f"tensor Gauss-Legendre (numpy leggauss) on the unit square/cube: shells {sh[0]}x{sh[0]} "
        f"panels x {sh[1]}x{sh[1]} points, solids {oh[0]}^3 panels x {oh[1]}^3 points (written), "
        f"checked against shells {sl[0]}x{sl[0]} x {sl[1]}x{sl[1]}, solids {ol[0]}^3 x {ol[1]}^3: "
        f"relative change (norm-wise, each of mass/cg/inertia) <= {change:.0e} on every deck, i.e. the "
        f"values are converged to round-off (accuracy ~{change:.0e} relative; the quad rule alone reaches "
        "round-off from 6x6 points on these warped quads). CONM2 at G+X (CID 0), X "
        "(CID -1), G+T X (CID>0, T = local Cartesian axes at the grid, e_r e_theta e_z for CORD2C) "
        "plus T J T^T, J = [[I11,-I21,-I31],[-I21,I22,-I32],[-I31,-I32,I33]]. "
        "mass = WTMASS sum m, cg = sum m x / sum m, inertia_cg = WTMASS (sum m (|d|^2 1 - d d^T) "
        "+ sum J) about the cg (negative products off the diagonal); sums with math.fsum."
    )


def self_check() -> None:
    """Closed-form cases for the integration routines (raise on failure)."""
    rule3, rule2 = rule_nd(3, *SOLID_HIGH), rule_nd(2, *SHELL_HIGH)
    rng = np.random.default_rng(7)
    # straight tetra: V = (G2-G1).((G3-G1)x(G4-G1))/6, centroid = corner mean
    g = np.array([[0.1, 0.2, 0.0], [1.3, 0.1, 0.2], [0.2, 1.1, -0.1], [0.3, 0.4, 0.9]])
    v_exact = float(np.dot(g[1] - g[0], np.cross(g[2] - g[0], g[3] - g[0]))) / 6
    mids = np.array([(g[a] + g[b]) / 2 for a, b in [(0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)]])
    for v, s in (solid_trilinear(g[[0, 1, 2, 2, 3, 3, 3, 3]], rule3),
                 solid_tetra10(np.vstack([g, mids]), rule3),
                 solid_tetra10(np.vstack([g, mids]), rule3, order=(0, 1, 2, 3))):
        assert abs(v - v_exact) < 1e-15 and np.allclose(s / v, g.mean(axis=0), rtol=0, atol=1e-15), (v, v_exact)
    # curved tetra10: two different Duffy collapses agree
    p10 = np.vstack([g, mids + 0.05 * rng.standard_normal((6, 3))])
    v1, s1 = solid_tetra10(p10, rule3)
    v2, s2 = solid_tetra10(p10, rule3, order=(2, 0, 3, 1))
    assert abs(v1 - v2) < 1e-15 and np.allclose(s1, s2, rtol=0, atol=1e-15), (v1, v2)
    # trilinear hexa = union of its 2 collapsed wedges when the faces are planar... use a
    # parallelepiped instead: V = |det[a b c]|, centroid = corner mean
    o, a, b, c = np.array([0.3, -0.2, 0.1]), np.array([1.0, 0.2, 0.1]), np.array([0.3, 0.9, 0.0]), np.array([0.2, 0.1, 1.4])
    h = np.array([o, o + a, o + a + b, o + b, o + c, o + a + c, o + a + b + c, o + b + c])
    v, s = solid_trilinear(h, rule3)
    assert abs(v - np.linalg.det(np.array([a, b, c]))) < 1e-14 and np.allclose(s / v, h.mean(axis=0), atol=1e-15)
    # the same parallelepiped as two wedges (G1 G2 G3 / G5 G6 G7 and G1 G3 G4 / G5 G7 G8)
    w1 = solid_trilinear(h[[0, 1, 2, 2, 4, 5, 6, 6]], rule3)
    w2 = solid_trilinear(h[[0, 2, 3, 3, 4, 6, 7, 7]], rule3)
    assert abs(w1[0] + w2[0] - v) < 1e-14 and np.allclose(w1[1] + w2[1], s, atol=1e-14)
    # flat triangle with linear density: m = A (m1+m2+m3)/3, moment = A/12 sum m_k (sum p + p_k)
    t = np.array([[0.0, 0.0, 0.0], [2.0, 0.3, 0.1], [0.4, 1.5, -0.2]])
    mu = np.array([1.0, 2.5, 0.7])
    area = 0.5 * np.linalg.norm(np.cross(t[1] - t[0], t[2] - t[0]))
    m, s = shell_quad(t[[0, 1, 2, 2]], mu[[0, 1, 2, 2]], rule2)
    assert abs(m - area * mu.sum() / 3) < 1e-14
    assert np.allclose(s, sum(area / 12 * mu[k] * (t.sum(axis=0) + t[k]) for k in range(3)), atol=1e-14)
    # flat parallelogram quad, constant density: m = |a x b|, centroid = corner mean
    q = np.array([o, o + a, o + a + b, o + b])
    m, s = shell_quad(q, np.ones(4), rule2)
    assert abs(m - np.linalg.norm(np.cross(a, b))) < 1e-14 and np.allclose(s / m, q.mean(axis=0), atol=1e-15)
    # hyperbolic paraboloid z = k x y over the unit square (a warped CQUAD4):
    # A = int int sqrt(1 + k^2 (x^2 + y^2)) dx dy, reference by scipy's adaptive dblquad
    from scipy.integrate import dblquad
    kk = 0.8
    q = np.array([[0, 0, 0], [1, 0, 0], [1, 1, kk], [0, 1, 0]], dtype=float)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # quadpack notes round-off at the requested 1e-15
        ref, _ = dblquad(lambda y, x: math.sqrt(1 + kk * kk * (x * x + y * y)), 0, 1, 0, 1, epsabs=1e-15, epsrel=1e-15)
    m, _ = shell_quad(q, np.ones(4), rule2)
    assert abs(m - ref) < 1e-14 * ref, (m, ref)


def main() -> int:
    self_check()
    ok = True
    worst = 0.0
    results = {}
    print(f"{'deck':<22} {'mass':>22} {'d_mass':>9} {'d_cg':>9} {'d_inertia':>9}  (LOW vs HIGH rule)")
    for stem in DECKS:
        model = read_deck(DECK_DIR / f"{stem}.bdf")
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            low = totals(model, mass_points(model, rule_nd(2, *SHELL_LOW), rule_nd(3, *SOLID_LOW)))
            high = totals(model, mass_points(model, rule_nd(2, *SHELL_HIGH), rule_nd(3, *SOLID_HIGH)))
        ch = rel_change(low, high)
        worst = max(worst, *ch)
        print(f"{stem:<22} {high['mass']!r:>22} {ch[0]:9.1e} {ch[1]:9.1e} {ch[2]:9.1e}")
        if max(ch) >= CONVERGENCE_LIMIT:
            print(f"  NOT CONVERGED: {max(ch):.2e} >= {CONVERGENCE_LIMIT:.0e}", file=sys.stderr)
            ok = False
        results[stem] = high
    # the provenance states the worst change over all decks, rounded up to a power of ten
    bound = 10.0 ** math.ceil(math.log10(max(worst, 1e-17)))
    for stem, r in results.items():
        out = {"provenance": provenance(bound), "mass": r["mass"], "cg": r["cg"], "inertia_cg": r["inertia_cg"]}
        (REF_DIR / f"{stem}.exact.json").write_text(json.dumps(out, indent=2) + "\n")
    # the three formats of one model describe the same model
    print("\nformat consistency (max relative difference vs *_small):")
    for m in MODELS:
        for k in ("large", "free"):
            print(f"  {m:14s} {k:5s} {max(rel_change(results[f'{m}_{k}'], results[f'{m}_small'])):.1e}")
    print(f"\nworst LOW/HIGH change {worst:.2e} (limit {CONVERGENCE_LIMIT:.0e}) -> {'ok' if ok else 'FAILED'}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
