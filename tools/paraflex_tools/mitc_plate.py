"""A flat Reissner-Mindlin plate of 4-node quads and 3-node triangles with the published MITC4
(Dvorkin & Bathe 1984) or MITC3 (Lee & Bathe 2004) assumed transverse shear, in numpy: the
independent computation paraflex's CQUAD4/CTRIA3 bending is checked against (MacNeal-Harder
strips in tools/calculix/macneal_harder.py, thin strips in tools/analytic/make_cases.py).

A plate ``c`` is any object with ``nodes`` ({grid: (x, y, z)}, z = 0), ``elems`` ([(eid,
connectivity)]), ``clamp`` (grids with every DOF fixed), ``E``, ``nu`` and ``t``, such as
:class:`FlatPlate`.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.linalg


@dataclass
class FlatPlate:
    """A flat mesh in the xy plane, its clamped grids and an isotropic material."""

    nodes: dict  # grid -> (x, y, z)
    elems: list  # (eid, grids)
    clamp: list
    E: float
    nu: float
    t: float


def solve_clamped(k, f, clamped: list, per_node: int):
    """u with K u = f on the free DOFs and u = 0 on every DOF of the `clamped` node indices
    (`per_node` DOFs each, node-major)."""
    fixed = {per_node * i + j for i in clamped for j in range(per_node)}
    free = [i for i in range(len(f)) if i not in fixed]
    u = np.zeros(len(f))
    u[free] = np.linalg.solve(k[np.ix_(free, free)], f[free])
    return u


def mitc_plate(c, forces: list, shear_factor: float = 0.833333) -> dict:
    """Displacements (0, 0, w) per grid of the flat CQUAD4/CTRIA3 mesh `c` (z = 0) as a
    Reissner-Mindlin plate ([`mitc_plate_stiffness`]) under out-of-plane `forces`, clamped grids
    fixed."""
    ids = sorted(c.nodes)
    index = {g: i for i, g in enumerate(ids)}
    k = mitc_plate_stiffness(c, shear_factor)
    f = np.zeros(3 * len(ids))
    for g, dof, value in forces:
        assert dof == 3, "out-of-plane loads only"
        f[3 * index[g]] += value
    u = solve_clamped(k, f, [index[g] for g in c.clamp], 3)
    return {g: (0.0, 0.0, u[3 * index[g]]) for g in ids}


def mitc_plate_modes(c, rho: float, count: int, shear_factor: float = 0.833333) -> list:
    """The `count` lowest natural frequencies [Hz] of the clamped plate of [`mitc_plate`] with
    its consistent mass: rho t N_i N_j on w and the rotary inertia rho t^3/12 N_i N_j on both
    rotations ([`plate_rule`]: exact for N_i N_j). Solved as M x = mu K x for the largest
    mu = 1/omega^2 (K's shear/bending contrast (L/t)^2 leaves M the better-scaled right-hand side
    at t/L = 1e-4)."""
    ids = sorted(c.nodes)
    index = {g: i for i, g in enumerate(ids)}
    k = mitc_plate_stiffness(c, shear_factor)
    m = np.zeros_like(k)
    for _, conn in c.elems:
        xy = np.array([c.nodes[g][:2] for g in conn])
        shape, points = plate_rule(len(conn))
        nn = np.zeros((len(conn), len(conn)))
        for r, s, weight in points:
            n, dr, ds = shape(r, s)
            nn += np.outer(n, n) * weight * abs(np.linalg.det(np.array([dr @ xy, ds @ xy])))
        for j, inertia in enumerate((rho * c.t, rho * c.t ** 3 / 12, rho * c.t ** 3 / 12)):
            dofs = [3 * index[g] + j for g in conn]
            m[np.ix_(dofs, dofs)] += inertia * nn
    fixed = {3 * index[g] + j for g in c.clamp for j in range(3)}
    free = [i for i in range(len(k)) if i not in fixed]
    nf = len(free)
    mu = scipy.linalg.eigh(m[np.ix_(free, free)], k[np.ix_(free, free)], eigvals_only=True, subset_by_index=[nf - count, nf - 1])
    return [float(math.sqrt(1 / x) / (2 * math.pi)) for x in mu[::-1]]


def plate_rule(nodes: int):
    """Shape functions (N, dN/dr, dN/ds at (r, s)) and integration points (r, s, weight) of the
    4-node quad (2 x 2 Gauss) or the 3-node triangle (3-point rule of degree 2)."""
    if nodes == 4:
        corners, gauss = [(-1, -1), (1, -1), (1, 1), (-1, 1)], 1 / math.sqrt(3)

        def shape(r, s):
            return (np.array([0.25 * (1 + a * r) * (1 + b * s) for a, b in corners]),
                    np.array([0.25 * a * (1 + b * s) for a, b in corners]),
                    np.array([0.25 * b * (1 + a * r) for a, b in corners]))
        return shape, [(a * gauss, b * gauss, 1.0) for a, b in corners]

    def shape(r, s):
        return np.array([1 - r - s, r, s]), np.array([-1.0, 1.0, 0.0]), np.array([-1.0, 0.0, 1.0])
    return shape, [(1 / 6, 1 / 6, 1 / 6), (2 / 3, 1 / 6, 1 / 6), (1 / 6, 2 / 3, 1 / 6)]


def mitc_plate_stiffness(c, shear_factor: float = 0.833333) -> np.ndarray:
    """Stiffness of the flat CQUAD4/CTRIA3 mesh `c` (z = 0) as a Reissner-Mindlin plate (w,
    theta_x, theta_y per grid in sorted grid order; beta = (theta_y, -theta_x), Nastran's rotation
    sense) with MITC4 or MITC3 transverse shear. Bending D_b = E t^3 / (12 (1 - nu^2)) [plane
    stress], shear D_s = shear_factor G t (PSHELL TS/T; 0.833333 is its default); quads 2 x 2
    Gauss, triangles the 3-point rule of degree 2.

    MITC4 (Dvorkin & Bathe 1984): covariant e_xi = dw/dxi + beta . dx/dxi tied at (0, +-1), e_eta at
    (+-1, 0), interpolated linearly across; MITC3 (Lee & Bathe 2004): e_rt at (1/2, 0), e_st at
    (0, 1/2), c = (e_rt - e_st) at (1/2, 1/2) minus e_rt(1/2, 0) plus e_st(0, 1/2),
    e_rt = e_rt(1/2, 0) + c s, e_st = e_st(0, 1/2) - c r; Cartesian shear gamma = J^-1 (e_r, e_s)."""
    ids = sorted(c.nodes)
    index = {g: i for i, g in enumerate(ids)}
    k = np.zeros((3 * len(ids), 3 * len(ids)))
    d_b = c.E * c.t ** 3 / 12 / (1 - c.nu ** 2) * np.array([[1, c.nu, 0], [c.nu, 1, 0], [0, 0, (1 - c.nu) / 2]])
    d_s = shear_factor * c.E / (2 * (1 + c.nu)) * c.t * np.eye(2)
    for _, conn in c.elems:
        xy = np.array([c.nodes[g][:2] for g in conn])
        m = len(conn)
        shape, points = plate_rule(m)

        def covariant(r, s, along_s):
            n, dr, ds = shape(r, s)
            dn = ds if along_s else dr
            x_n, y_n = dn @ xy
            row = np.zeros(3 * m)
            row[0::3], row[1::3], row[2::3] = dn, -n * y_n, n * x_n
            return row
        ke = np.zeros((3 * m, 3 * m))
        for r, s, weight in points:
            _, dr, ds = shape(r, s)
            jac = np.array([dr @ xy, ds @ xy])
            inv = np.linalg.inv(jac)
            nx, ny = inv[0, 0] * dr + inv[0, 1] * ds, inv[1, 0] * dr + inv[1, 1] * ds
            b_b = np.zeros((3, 3 * m))
            b_b[0, 2::3], b_b[1, 1::3], b_b[2, 2::3], b_b[2, 1::3] = nx, -ny, ny, -nx
            if m == 4:
                e_r = 0.5 * (1 + s) * covariant(0, 1, False) + 0.5 * (1 - s) * covariant(0, -1, False)
                e_s = 0.5 * (1 + r) * covariant(1, 0, True) + 0.5 * (1 - r) * covariant(-1, 0, True)
            else:
                e1, e2 = covariant(0.5, 0, False), covariant(0, 0.5, True)
                cc = (covariant(0.5, 0.5, False) - e1) - (covariant(0.5, 0.5, True) - e2)
                e_r, e_s = e1 + cc * s, e2 - cc * r
            b_s = inv @ np.vstack([e_r, e_s])
            ke += (b_b.T @ d_b @ b_b + b_s.T @ d_s @ b_s) * weight * abs(np.linalg.det(jac))
        dofs = [3 * index[g] + j for g in conn for j in range(3)]
        k[np.ix_(dofs, dofs)] += ke
    return k
