#!/usr/bin/env python3
"""CBUSH statics against a separately written numpy model of the bush: six springs along and
about the element axes acting at the spring location P, rigidly carried by both grids.

Two bushes, each loaded by a force and a moment at its free grid:

- CBUSH 1 between grid 1 (clamped) and grid 2 at (2, 1, -0.5), axes from the orientation grid
  GO = 3 (x along 1->2, y in the plane of x and 1->3), the spring at S = 0.3 along 1->2;
- CBUSH 2 grounded at grid 5 (no GB), axes of the rotated rectangular system 10 (CID), the spring
  offset from grid 5 by (0.5, 0.2, -0.3) in system 10 (OCID = 10).

The model here, written from the definition: a grid with translation u and rotation w carries P
by u + w x (P - x); the relative motion at P, projected on the element axes e_i, stretches spring
i (translations: k1..k3, rotations w_b - w_a: k4..k6). Stiffness columns come from unit DOF
motions through numpy.cross (no skew-matrix algebra, unlike src/fe/bush.rs); the free grid's
6 x 6 block is solved for the load. Checks: K is symmetric, a rigid motion of both grids costs
nothing.

Writes ``decks/verify/independent/cbush_static.dat`` and ``reference/analytic/cbush_static.json``.
Run: ``.venv/bin/python tools/analytic/cbush_static.py``.
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
DECK = ROOT / "decks" / "verify" / "independent" / "cbush_static.dat"
REF = ROOT / "reference" / "analytic" / "cbush_static.json"

K = [1.0e3, 2.0e3, 3.0e3, 4.0e3, 5.0e3, 6.0e3]
X = {1: [0.0, 0.0, 0.0], 2: [2.0, 1.0, -0.5], 3: [0.0, 1.0, 1.0], 5: [4.0, 0.0, 0.0]}
# CORD2R 10: origin (1, 2, 3), z axis through A + (0, 0.6, 0.8), xz-plane point A + (1, 0, 0)
ORIGIN = np.array([1.0, 2.0, 3.0])
ZDIR = np.array([0.0, 0.6, 0.8])
XZPT = np.array([1.0, 0.0, 0.0])
OFFSET = [0.5, 0.2, -0.3]
S = 0.3
LOADS = {2: ([10.0, -5.0, 3.0], [2.0, 1.0, -4.0]), 5: ([-3.0, 7.0, 2.0], [1.5, -2.0, 0.5])}


def system10() -> np.ndarray:
    """Rows: the axes of CORD2R 10 in basic."""
    z = ZDIR / np.linalg.norm(ZDIR)
    y = np.cross(z, XZPT)
    y /= np.linalg.norm(y)
    return np.array([np.cross(y, z), y, z])


def stiffness(axes: np.ndarray, p: np.ndarray, xa: np.ndarray, xb: np.ndarray | None) -> np.ndarray:
    """K over (u_a, w_a[, u_b, w_b]) from unit DOF motions."""
    n = 12 if xb is not None else 6
    t = np.zeros((6, n))
    for j in range(n):
        q = np.zeros(n)
        q[j] = 1.0
        ua, wa = q[0:3], q[3:6]
        carried_a = ua + np.cross(wa, p - xa)
        if xb is not None:
            ub, wb = q[6:9], q[9:12]
            carried_b = ub + np.cross(wb, p - xb)
        else:
            carried_b, wb = np.zeros(3), np.zeros(3)
        t[:3, j] = axes @ (carried_b - carried_a)
        t[3:, j] = axes @ (wb - wa)
    kk = t.T @ np.diag(K) @ t
    assert np.allclose(kk, kk.T, atol=1e-9)
    return kk


def main() -> None:
    xa, xb, xo = (np.array(X[i]) for i in (1, 2, 3))
    ex = (xb - xa) / np.linalg.norm(xb - xa)
    ez = np.cross(ex, xo - xa)
    ez /= np.linalg.norm(ez)
    axes1 = np.array([ex, np.cross(ez, ex), ez])
    k1 = stiffness(axes1, xa + S * (xb - xa), xa, xb)
    # rigid motion of both grids: no force
    w, u = np.array([0.1, 0.4, -0.3]), np.array([0.3, -0.2, 0.7])
    rigid = np.concatenate([u, w, u + np.cross(w, xb - xa), w])
    assert np.abs(k1 @ rigid).max() < 1e-9
    f2 = np.concatenate(LOADS[2])
    u2 = np.linalg.solve(k1[6:, 6:], f2)

    x5 = np.array(X[5])
    axes2 = system10()
    p2 = x5 + axes2.T @ np.array(OFFSET)
    k2 = stiffness(axes2, p2, x5, None)
    u5 = np.linalg.solve(k2, np.concatenate(LOADS[5]))

    kline = ",".join(f"{k:.1f}" for k in K)
    deck = f"""$ written by tools/analytic/cbush_static.py
SOL 101
CEND
SPC = 1
LOAD = 2
BEGIN BULK
GRID,1,,{X[1][0]},{X[1][1]},{X[1][2]}
GRID,2,,{X[2][0]},{X[2][1]},{X[2][2]}
GRID,3,,{X[3][0]},{X[3][1]},{X[3][2]}
GRID,5,,{X[5][0]},{X[5][1]},{X[5][2]}
CORD2R,10,,{ORIGIN[0]},{ORIGIN[1]},{ORIGIN[2]},{ORIGIN[0]+ZDIR[0]},{ORIGIN[1]+ZDIR[1]},{ORIGIN[2]+ZDIR[2]},
,{ORIGIN[0]+XZPT[0]},{ORIGIN[1]+XZPT[1]},{ORIGIN[2]+XZPT[2]}
CBUSH,1,7,1,2,3,,,,
,{S}
CBUSH,2,7,5,,,,,10
,,10,{OFFSET[0]},{OFFSET[1]},{OFFSET[2]}
PBUSH,7,K,{kline}
SPC1,1,123456,1,3
FORCE,2,2,,1.0,{LOADS[2][0][0]},{LOADS[2][0][1]},{LOADS[2][0][2]}
MOMENT,2,2,,1.0,{LOADS[2][1][0]},{LOADS[2][1][1]},{LOADS[2][1][2]}
FORCE,2,5,,1.0,{LOADS[5][0][0]},{LOADS[5][0][1]},{LOADS[5][0][2]}
MOMENT,2,5,,1.0,{LOADS[5][1][0]},{LOADS[5][1][1]},{LOADS[5][1][2]}
ENDDATA
"""
    DECK.parent.mkdir(parents=True, exist_ok=True)
    DECK.write_text(deck)
    ref = {
        "source": "tools/analytic/cbush_static.py: numpy model of the CBUSH springs at P (unit DOF motions, numpy.cross)",
        "deck": "decks/verify/independent/cbush_static.dat",
        "displacement": {"2": u2.tolist(), "5": u5.tolist()},
    }
    REF.write_text(json.dumps(ref, indent=1) + "\n")
    print(f"u2 = {u2}\nu5 = {u5}")


if __name__ == "__main__":
    main()
