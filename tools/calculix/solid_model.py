"""A small, separately written numpy model of the linear-elastic solids CTETRA 4 / C3D4,
CTETRA 10 / C3D10, CPENTA 6 / C3D6, CHEXA 20 / C3D20 and CPENTA 15 / C3D15: isoparametric shape functions, B = ∂N/∂x, K = ∫ Bᵀ D B dV
and M = ρ ∫ Nᵀ N dV, both under a quadrature rule chosen by the caller, assembled densely and
solved with scipy. Used by solid_same_mesh.py in two ways: with CalculiX's quadrature it must
reproduce ccx on the same mesh (a check of this model), with exact quadrature it is the reference
paraflex is compared with.

Node orders (Nastran = CalculiX): tetra G1..G4 corners at natural (0,0,0), (1,0,0), (0,1,0),
(0,0,1), G5..G10 on edges 1-2, 2-3, 3-1, 1-4, 2-4, 3-4; wedge G1..G3 the triangle (0,0), (1,0),
(0,1) at ζ = -1, G4..G6 above them at ζ = +1; hexa20 G1..G8 corners (±1)^3 (G1..G4 at ζ = -1
counter-clockwise from (-1,-1)), G9..G12 on edges 1-2, 2-3, 3-4, 4-1, G13..G16 on 1-5, 2-6, 3-7,
4-8, G17..G20 on 5-6, 6-7, 7-8, 8-5 (Nastran; CalculiX puts 13..16 and 17..20 the other way
round); wedge15 G7..G9 on 1-2, 2-3, 3-1, G10..G12 on 1-4, 2-5, 3-6, G13..G15 on 4-5, 5-6, 6-4.
"""
from __future__ import annotations

import numpy as np
import scipy.linalg


def _line_gauss(n: int):
    x, w = np.polynomial.legendre.leggauss(n)
    return x, w


def tet_exact_rule(n: int = 5):
    """Conical-product (Stroud) rule on the unit tetrahedron: n Gauss points in each collapsed
    direction integrate every polynomial of degree ≤ 2n - 3 exactly (degree 7 for n = 5)."""
    x, w = _line_gauss(n)
    u, wu = 0.5 * (x + 1), 0.5 * w
    pts, wts = [], []
    for a, wa in zip(u, wu):
        for b, wb in zip(u, wu):
            for c, wc in zip(u, wu):
                pts.append((a, (1 - a) * b, (1 - a) * (1 - b) * c))
                wts.append(wa * wb * wc * (1 - a) ** 2 * (1 - b))
    return np.array(pts), np.array(wts)


def tri_exact_rule(n: int = 4):
    """Collapsed Gauss rule on the unit triangle (degree 2n - 2)."""
    x, w = _line_gauss(n)
    u, wu = 0.5 * (x + 1), 0.5 * w
    pts = [(a, (1 - a) * b) for a in u for b in u]
    wts = [wa * wb * (1 - a) for a, wa in zip(u, wu) for wb in wu]
    return np.array(pts), np.array(wts)


def wedge_rule(tri, nz: int):
    (tp, tw), (zx, zw) = tri, _line_gauss(nz)
    pts = [(p[0], p[1], z) for p in tp for z in zx]
    wts = [a * b for a in tw for b in zw]
    return np.array(pts), np.array(wts)


# CalculiX 2.20 gauss points (gauspoints.f; e_c3d.f with intscheme = 0)
CCX_TET1 = (np.array([[0.25, 0.25, 0.25]]), np.array([1.0 / 6.0]))
_A, _B = 0.5854101966249685, 0.1381966011250105
CCX_TET4 = (np.array([[_B, _B, _B], [_A, _B, _B], [_B, _A, _B], [_B, _B, _A]]), np.full(4, 1.0 / 24.0))
CCX_WEDGE2 = (np.array([[1 / 3, 1 / 3, -1 / np.sqrt(3)], [1 / 3, 1 / 3, 1 / np.sqrt(3)]]), np.array([0.5, 0.5]))
# C3D15: the 3-point interior triangle rule (degree 2) x 3 Gauss points through the thickness (with
# these points this model reproduces ccx 2.20's C3D15 cantilever to its 7 printed digits)
CCX_WEDGE9 = wedge_rule((np.array([[1 / 6, 1 / 6], [2 / 3, 1 / 6], [1 / 6, 2 / 3]]), np.full(3, 1 / 6)), 3)


def gauss_cube_rule(n: int):
    """n x n x n Gauss-Legendre on [-1, 1]^3 (degree 2n - 1 per direction)."""
    x, w = _line_gauss(n)
    pts = [(a, b, c) for a in x for b in x for c in x]
    wts = [wa * wb * wc for wa in w for wb in w for wc in w]
    return np.array(pts), np.array(wts)


_HEX_CORNERS = np.array([[-1, -1, -1], [1, -1, -1], [1, 1, -1], [-1, 1, -1],
                         [-1, -1, 1], [1, -1, 1], [1, 1, 1], [-1, 1, 1]], float)
_HEX20_EDGES = ((0, 1), (1, 2), (2, 3), (3, 0), (0, 4), (1, 5), (2, 6), (3, 7),
                (4, 5), (5, 6), (6, 7), (7, 4))
HEX20_NODES = np.vstack([_HEX_CORNERS] + [0.5 * (_HEX_CORNERS[a] + _HEX_CORNERS[b]) for a, b in _HEX20_EDGES])
WEDGE15_EDGES = ((0, 1), (1, 2), (2, 0), (0, 3), (1, 4), (2, 5), (3, 4), (4, 5), (5, 3))


def _hexa20(p):
    """Serendipity 20-node brick: N and dN/dξ from the natural node coordinates."""
    n, dn = np.zeros(20), np.zeros((20, 3))
    for a, c in enumerate(HEX20_NODES):
        f = 1 + c * p  # per-direction linear factors (c_k = 0 on a mid-side's own direction)
        if a < 8:
            s = c @ p - 2
            n[a] = f.prod() * s / 8
            for k in range(3):
                rest = np.prod(np.delete(f, k))
                dn[a, k] = c[k] * rest * (s + f[k]) / 8  # ∂(Πf)/∂ξ_k s + Πf ∂s/∂ξ_k
        else:
            k0 = int(np.flatnonzero(c == 0)[0])
            g = f.copy()
            g[k0] = 1 - p[k0] ** 2
            dg = c.copy()
            dg[k0] = -2 * p[k0]
            n[a] = g.prod() / 4
            for k in range(3):
                dn[a, k] = dg[k] * np.prod(np.delete(g, k)) / 4
    return n, dn


def _wedge15(p):
    """15-node wedge: corners L(2L - 1)(1 ± ζ)/2 - L(1 - ζ²)/2, triangle mid-sides
    2 L_a L_b (1 ± ζ), vertical mid-sides L (1 - ζ²); derivatives by the chain rule in (L, ζ)."""
    x, y, z = p
    l = np.array([1 - x - y, x, y])
    dl = np.array([[-1, -1], [1, 0], [0, 1]], float)
    n, dn = np.zeros(15), np.zeros((15, 3))
    for a in range(6):
        t, s = a % 3, (-1.0 if a < 3 else 1.0)
        n[a] = 0.5 * l[t] * (2 * l[t] - 1) * (1 + s * z) - 0.5 * l[t] * (1 - z * z)
        d_dl = 0.5 * (4 * l[t] - 1) * (1 + s * z) - 0.5 * (1 - z * z)
        dn[a, :2] = d_dl * dl[t]
        dn[a, 2] = 0.5 * l[t] * (2 * l[t] - 1) * s + l[t] * z
    for m, (a, b) in enumerate(WEDGE15_EDGES, 6):
        ta, tb = a % 3, b % 3
        if ta == tb:
            n[m] = l[ta] * (1 - z * z)
            dn[m, :2] = (1 - z * z) * dl[ta]
            dn[m, 2] = -2 * z * l[ta]
        else:
            s = -1.0 if a < 3 else 1.0
            n[m] = 2 * l[ta] * l[tb] * (1 + s * z)
            dn[m, :2] = 2 * (1 + s * z) * (dl[ta] * l[tb] + l[ta] * dl[tb])
            dn[m, 2] = 2 * l[ta] * l[tb] * s
    return n, dn


def shape(kind: str, p):
    """(N, dN/dξ) at natural point p."""
    p = np.asarray(p, float)
    if kind == "hexa20":
        return _hexa20(p)
    if kind == "wedge15":
        return _wedge15(p)
    x, y, z = p
    if kind in ("tet4", "tet10"):
        l = np.array([1 - x - y - z, x, y, z])
        dl = np.array([[-1, -1, -1], [1, 0, 0], [0, 1, 0], [0, 0, 1]], float)
        if kind == "tet4":
            return l, dl
        n = list(l * (2 * l - 1))
        dn = [(4 * l[a] - 1) * dl[a] for a in range(4)]
        for a, b in ((0, 1), (1, 2), (2, 0), (0, 3), (1, 3), (2, 3)):
            n.append(4 * l[a] * l[b])
            dn.append(4 * (dl[a] * l[b] + l[a] * dl[b]))
        return np.array(n), np.array(dn)
    l = np.array([1 - x - y, x, y])
    dl = np.array([[-1, -1], [1, 0], [0, 1]], float)
    n, dn = np.zeros(6), np.zeros((6, 3))
    for a in range(3):
        for b, s in ((a, -1.0), (a + 3, 1.0)):
            h = 0.5 * (1 + s * z)
            n[b] = l[a] * h
            dn[b] = [dl[a, 0] * h, dl[a, 1] * h, 0.5 * s * l[a]]
    return n, dn


def elasticity(e: float, nu: float):
    lam, mu = e * nu / ((1 + nu) * (1 - 2 * nu)), e / (2 * (1 + nu))
    d = np.zeros((6, 6))
    d[:3, :3] = lam
    d[range(3), range(3)] += 2 * mu
    d[range(3, 6), range(3, 6)] = mu
    return d


def element(kind, xyz, d, rho, k_rule, m_rule):
    """Element K and M (3n x 3n, node-major: row 3a + c is component c of node a)."""
    n = xyz.shape[0]
    k = np.zeros((3 * n, 3 * n))
    m = np.zeros((3 * n, 3 * n))
    for p, w in zip(*k_rule):
        _, dn = shape(kind, p)
        jac = dn.T @ xyz  # J[i, j] = ∂x_j/∂ξ_i
        g = np.linalg.solve(jac, dn.T).T  # ∂N/∂x
        b = np.zeros((6, 3 * n))
        for a in range(n):
            gx, gy, gz = g[a]
            b[0, 3 * a], b[1, 3 * a + 1], b[2, 3 * a + 2] = gx, gy, gz
            b[3, 3 * a], b[3, 3 * a + 1] = gy, gx  # γxy
            b[4, 3 * a + 1], b[4, 3 * a + 2] = gz, gy  # γyz
            b[5, 3 * a], b[5, 3 * a + 2] = gz, gx  # γzx
        k += w * np.linalg.det(jac) * b.T @ d @ b
    for p, w in zip(*m_rule):
        nn, dn = shape(kind, p)
        jac = dn.T @ xyz
        m += w * np.linalg.det(jac) * rho * np.kron(np.outer(nn, nn), np.eye(3))
    return k, m


def assemble(kind, nodes, elems, e, nu, rho, k_rule, m_rule):
    """Global K, M over the translations of `nodes` [(id, x, y, z)], ordered by node id."""
    index = {nid: i for i, (nid, *_) in enumerate(sorted(nodes))}
    xyz = {nid: np.array(c) for nid, *c in nodes}
    ndof = 3 * len(index)
    kg, mg = np.zeros((ndof, ndof)), np.zeros((ndof, ndof))
    d = elasticity(e, nu)
    for conn in elems:
        ke, me = element(kind, np.array([xyz[c] for c in conn]), d, rho, k_rule, m_rule)
        dofs = np.array([3 * index[c] + j for c in conn for j in range(3)])
        kg[np.ix_(dofs, dofs)] += ke
        mg[np.ix_(dofs, dofs)] += me
    return index, kg, mg


def static_and_modes(kind, nodes, elems, e, nu, rho, k_rule, m_rule, fixed, loads, nmodes):
    """Displacements {id: (ux, uy, uz)} under nodal `loads` {id: (fx, fy, fz)} with the `fixed`
    grids clamped in T1-T3, the lowest `nmodes` frequencies (Hz), and the 2-norm condition
    number of the constrained K (it bounds the round-off of any solver's displacements)."""
    index, k, m = assemble(kind, nodes, elems, e, nu, rho, k_rule, m_rule)
    fixed_dofs = {3 * index[g] + j for g in fixed for j in range(3)}
    free = np.array([i for i in range(k.shape[0]) if i not in fixed_dofs])
    f = np.zeros(k.shape[0])
    for g, v in loads.items():
        f[3 * index[g]:3 * index[g] + 3] += v
    u = np.zeros(k.shape[0])
    kff = k[np.ix_(free, free)]
    u[free] = scipy.linalg.solve(kff, f[free], assume_a="pos")
    # lowest modes of K φ = λ M φ; M may be singular (one-point mass): solve M φ = μ K φ instead,
    # μ = 1/λ, whose largest μ are the lowest λ
    mu = scipy.linalg.eigh(m[np.ix_(free, free)], kff, eigvals_only=True)
    lam = 1.0 / mu[::-1][:nmodes]
    freqs = np.sqrt(lam) / (2 * np.pi)
    disp = {nid: u[3 * i:3 * i + 3].tolist() for nid, i in index.items()}
    return disp, freqs.tolist(), float(np.linalg.cond(kff))
