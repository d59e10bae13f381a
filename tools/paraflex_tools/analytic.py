"""Reference values shared by the analytic verification cases (tools/analytic/make_cases.py) and
the scene generators (meshes/plates.py): the materials and literature sources they cite, the 1-D
Timoshenko beam element the shell and solid meshes are compared with, and the Timoshenko/Mindlin
dispersion relation."""
from __future__ import annotations

import math

import numpy as np
from scipy import linalg

STEEL = {"E": 210.0e9, "nu": 0.3, "rho": 7850.0}
ALU = {"E": 70.0e9, "nu": 0.33, "rho": 2700.0}
KAPPA_SHELL = 5.0 / 6.0  # PSHELL TS/T written explicitly as 5/6

BLEVINS = ('Blevins, R. D., "Formulas for Natural Frequency and Mode Shape", Van Nostrand '
           'Reinhold 1979, Table 8-1 (uniform single-span Euler-Bernoulli beams, clamped-free)')
BLEVINS_TORSION = ('Blevins 1979, Table 8-19 (torsional vibration of uniform shafts, fixed-free); '
                   'Timoshenko & Goodier "Theory of Elasticity" 3rd ed. 1970, sec. 109 '
                   '(torsion constant of a rectangle)')
LEISSA = ('Leissa, A. W., "Vibration of Plates", NASA SP-160, 1969, ch. 4 (rectangular plate '
          'simply supported on all edges, closed form) ')
TIMOSHENKO_BEAM = ('Timoshenko beam frequency equation for clamped-free ends: Huang, T. C., '
                   'J. Appl. Mech. 28 (1961) 579-584; shear coefficient of a rectangle: Cowper, '
                   'J. Appl. Mech. 33 (1966) 335-340, kappa = 10(1+nu)/(12+11nu)')
ROARK = ('Roark\'s Formulas for Stress and Strain (Young & Budynas, 7th ed. 2002), Table 8.1 '
         'case 1a (cantilever, end load) plus the transverse shear deflection P L/(kappa G A)')
JONES = ('Jones, R. M., "Mechanics of Composite Materials", 2nd ed. 1999, eqs. 2.84-2.85 '
         '(reduced stiffness Q), 2.85 (transformed Qbar), 4.22-4.24 (A, B, D)')


def timoshenko_fe_1d(L, EI, kGA, mA, mI, n, nmodes, bc="cf", load=None, full=False):
    """1D analogue of the shell/solid elements: two-node Timoshenko elements, linear w and psi,
    one-point (constant) transverse shear strain (the MITC4 tying gives exactly this in
    cylindrical bending), consistent translational and rotary mass.  bc: 'cf' clamped-free,
    'ss' simply supported.  Returns frequencies (Hz) or, with load=P, the tip deflection (with
    full=True the nodal vector [w0, psi0, w1, psi1, ...] of every node)."""
    h = L / n
    nd = 2 * (n + 1)
    K = np.zeros((nd, nd))
    M = np.zeros((nd, nd))
    kb = EI / h * np.array([[0, 0, 0, 0], [0, 1, 0, -1], [0, 0, 0, 0], [0, -1, 0, 1.0]])
    B = np.array([-1 / h, -0.5, 1 / h, -0.5])
    ks = kGA * h * np.outer(B, B)
    mw = mA * h / 6 * np.array([[2, 1], [1, 2.0]])
    mr = mI * h / 6 * np.array([[2, 1], [1, 2.0]])
    for e in range(n):
        d = [2 * e, 2 * e + 1, 2 * e + 2, 2 * e + 3]
        K[np.ix_(d, d)] += kb + ks
        M[np.ix_([d[0], d[2]], [d[0], d[2]])] += mw
        M[np.ix_([d[1], d[3]], [d[1], d[3]])] += mr
    if bc == "cf":
        free = list(range(2, nd))
    else:
        free = [i for i in range(nd) if i not in (0, nd - 2)]
    Kf, Mf = K[np.ix_(free, free)], M[np.ix_(free, free)]
    if load is not None:
        F = np.zeros(nd)
        F[nd - 2] = load
        u = np.linalg.solve(Kf, F[free])
        if full:
            out = np.zeros(nd)
            out[free] = u
            return out
        return u[free.index(nd - 2)]
    lam = linalg.eigh(Kf, Mf, eigvals_only=True, subset_by_index=[0, nmodes - 1])
    return np.sqrt(lam) / (2 * math.pi)


def timoshenko_dispersion(k, EI, kGA, mA, mI):
    """Flexural branch of the Timoshenko / Mindlin dispersion relation (lower root in w^2):
    (mA w^2 - kGA k^2)(mI w^2 - EI k^2 - kGA) - (kGA k)^2 = 0."""
    a = mA * mI
    b = -(mA * (EI * k * k + kGA) + mI * kGA * k * k)
    c = kGA * k * k * EI * k * k
    w2 = 2 * c / (-b + math.sqrt(b * b - 4 * a * c))  # the small root, without cancellation
    return math.sqrt(w2) / (2 * math.pi)
