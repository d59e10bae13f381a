#!/usr/bin/env python3
"""Ply stresses, strains and failure indices of a laminate under a known membrane resultant, by
classical lamination theory written from the textbook (Jones, *Mechanics of Composite
Materials*, 2nd ed., 1999: eq. 2.61 for Q, 2.80-2.84 for the transformation, 4.22 for A;
Tsai-Wu eq. 2.150-2.155 with the given F12; Tsai-Hill eq. 2.144), independently of paraflex's
code.

Laminate: carbon/epoxy MAT8 (E1 140 GPa, E2 10 GPa, ν12 0.3, G12 5 GPa, G1Z G2Z 5 GPa / 3.5 GPa),
ply 0.125 mm, [0/30/-60/90]s (A16, A26 non-zero), resultant N = (Nx, Ny, Nxy) =
(120, -40, 35) kN/m, no moment. A symmetric laminate has B = 0, so ε0 = A⁻¹N and κ = 0; every
ply has the laminate strain ε0 rotated into its axes, σ = Q ε.

Rotation (engineering strains, laminate x,y -> ply 1,2 at fibre angle θ, c = cos θ, s = sin θ):
    ε1 = c²εx + s²εy + cs γxy,  ε2 = s²εx + c²εy − cs γxy,  γ12 = −2cs εx + 2cs εy + (c² − s²) γxy
Cross-check in this script: the same strains from the tensor rotation R ε_tensor Rᵀ, and
Σ_k t_k σ_xy,k (stresses rotated back to x,y) = N.

Failure indices (allowables Xt 1500, Xc 1200, Yt 50, Yc 250, S 70 MPa, F12 -1.0e-18 /Pa²):
    Tsai-Wu  F1σ1 + F2σ2 + F11σ1² + F22σ2² + F66τ12² + 2F12σ1σ2,
             F1 = 1/Xt − 1/Xc, F2 = 1/Yt − 1/Yc, F11 = 1/(XtXc), F22 = 1/(YtYc), F66 = 1/S²
    Hill     σ1²/X² − σ1σ2/X² + σ2²/Y² + τ12²/S², X = Xt or Xc by the sign of σ1, Y by σ2

Writes reference/analytic/pcomp_membrane_plies.json. Run: .venv/bin/python tools/analytic/clt_plies.py
"""

import json
import pathlib

import numpy as np

ROOT = pathlib.Path(__file__).resolve().parents[2]
OUT = ROOT / "reference/analytic/pcomp_membrane_plies.json"

E1, E2, NU12, G12, G1Z, G2Z = 140e9, 10e9, 0.3, 5e9, 5e9, 3.5e9
XT, XC, YT, YC, S, F12 = 1500e6, 1200e6, 50e6, 250e6, 70e6, -1.0e-18
T_PLY = 0.125e-3
HALF = [0.0, 30.0, -60.0, 90.0]
LAYUP = HALF + HALF[::-1]
N = np.array([120e3, -40e3, 35e3])


def q_matrix():
    nu21 = NU12 * E2 / E1
    d = 1.0 - NU12 * nu21
    return np.array([[E1 / d, NU12 * E2 / d, 0.0], [NU12 * E2 / d, E2 / d, 0.0], [0.0, 0.0, G12]])


def strain_to_ply(theta_deg):
    c, s = np.cos(np.radians(theta_deg)), np.sin(np.radians(theta_deg))
    return np.array(
        [[c * c, s * s, c * s], [s * s, c * c, -c * s], [-2 * c * s, 2 * c * s, c * c - s * s]]
    )


def strain_to_ply_by_tensor(eps, theta_deg):
    """The same rotation through the strain tensor: ε' = R ε Rᵀ, R rows = ply axes."""
    c, s = np.cos(np.radians(theta_deg)), np.sin(np.radians(theta_deg))
    r = np.array([[c, s], [-s, c]])
    et = np.array([[eps[0], eps[2] / 2], [eps[2] / 2, eps[1]]])
    p = r @ et @ r.T
    return np.array([p[0, 0], p[1, 1], 2 * p[0, 1]])


def stress_to_laminate(sig, theta_deg):
    c, s = np.cos(np.radians(theta_deg)), np.sin(np.radians(theta_deg))
    r = np.array([[c, s], [-s, c]])
    st = np.array([[sig[0], sig[2]], [sig[2], sig[1]]])
    p = r.T @ st @ r
    return np.array([p[0, 0], p[1, 1], p[0, 1]])


def tsai_wu(s1, s2, t12):
    f1, f2 = 1 / XT - 1 / XC, 1 / YT - 1 / YC
    f11, f22, f66 = 1 / (XT * XC), 1 / (YT * YC), 1 / S**2
    return f1 * s1 + f2 * s2 + f11 * s1**2 + f22 * s2**2 + f66 * t12**2 + 2 * F12 * s1 * s2


def hill(s1, s2, t12):
    x = XT if s1 >= 0 else XC
    y = YT if s2 >= 0 else YC
    return s1**2 / x**2 - s1 * s2 / x**2 + s2**2 / y**2 + t12**2 / S**2


def main():
    q = q_matrix()
    a = np.zeros((3, 3))
    for th in LAYUP:
        t = strain_to_ply(th)
        qbar = t.T @ q @ t
        a += qbar * T_PLY
    eps0 = np.linalg.solve(a, N)
    h = T_PLY * len(LAYUP)
    z = -h / 2 + T_PLY * (np.arange(len(LAYUP)) + 0.5)
    plies, back = [], np.zeros(3)
    for k, th in enumerate(LAYUP):
        e = strain_to_ply(th) @ eps0
        assert np.allclose(e, strain_to_ply_by_tensor(eps0, th), rtol=0, atol=1e-15)
        sig = q @ e
        back += stress_to_laminate(sig, th) * T_PLY
        plies.append(
            {
                "ply": k + 1,
                "theta_deg": th,
                "z": z[k],
                "strain": list(e),
                "stress": list(sig),
                "tsai_wu": tsai_wu(*sig),
                "hill": hill(*sig),
            }
        )
    assert np.allclose(back, N, rtol=1e-12, atol=1e-6), (back, N)
    ref = {
        "case": "pcomp_membrane_plies",
        "provenance": "tools/analytic/clt_plies.py: classical lamination theory in numpy from Jones (1999), independent of paraflex; checks: tensor rotation of the strains, Σ t_k σ_k = N",
        "material": {"E1": E1, "E2": E2, "NU12": NU12, "G12": G12, "G1Z": G1Z, "G2Z": G2Z},
        "allowables": {"Xt": XT, "Xc": XC, "Yt": YT, "Yc": YC, "S": S, "F12": F12},
        "ply_thickness": T_PLY,
        "layup_deg": LAYUP,
        "resultant_N": list(N),
        "laminate_strain": list(eps0),
        "plies": plies,
        "tolerance": {
            "rel": 1e-9,
            "why": "a constant membrane state is exact for CTRIA3 (and the plate patch), so only the solve's round-off separates paraflex from CLT",
        },
    }
    OUT.write_text(json.dumps(ref, indent=2) + "\n")
    print(f"wrote {OUT.relative_to(ROOT)}: ε0 = {eps0}")


if __name__ == "__main__":
    main()
