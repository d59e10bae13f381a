"""The rigid Robolink chain computed here without paraflex (static holding torques and the
end effector's kinematics): the references of ``tests/fmb_robot.rs``.

Input: ``reference/robot/mass_properties.json`` (``tools/robot/model.py``: every body's mass
and centre of mass in the upright reference configuration, the motor axes). At a pose
θ = (θ1 … θ5) each body's centre of mass is carried through the serial chain, from the
distal motor inwards (x ↦ p_k + R_k(θ_k)(x − p_k) for every motor k the body lies beyond,
R_k the rotation about the axis n_k). With gravity g = −9.81 e_z the static torque that motor
k holds is minus the moment of the weights of everything beyond it about its axis,

    T_k = −n_k · Σ_{i beyond k} (x_i − p_k) × m_i g,

the vertical reaction of the plate's spherical corner c1 = (−a, −a) of its 3-2-1 mount (SPH
at c1, INLINE at c2 = (a, −a), INPLANE at c3 = (−a, a)) follows from the moment balance of
the whole system, R1 = −g Σ m_i (x_i + y_i) / (2a), and the EE centre is carried like a
centre of mass. Along trajectory #1 the EE centre of the rigid chain at the drive targets θ(t)
(the tables of ``decks/robot/fmb/trajectory1.csv``) is the rigid kinematic reference x_R(t)
of eq. 4.13 for the test's window.

Run: ``.venv/bin/python tools/robot/rigid_chain.py`` (writes
``reference/robot/rigid_chain.json``).
"""
from __future__ import annotations

import itertools
import json
import math
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]
PROVENANCE = "tools/robot/rigid_chain.py"
WINDOW = (0.0, 0.8, 0.01)       # trajectory #1 window of the test: start, end, output step [s]
G = 9.81
HALF_SIDE = 0.5                 # plate corners at (±a, ±a)
# the bodies each motor turns (the chain: P – M1 – L1 – M2 – L2 – M3 – L3 – M4 – L4M5 – M5 – EE)
BEYOND = {
    "M1": ["M1I", "L1", "M2E", "M2I", "L2R", "L2L", "M3E", "M3I", "L3R", "L3L", "M4E", "M4I",
           "L4M5", "EE"],
    "M2": ["M2I", "L2R", "L2L", "M3E", "M3I", "L3R", "L3L", "M4E", "M4I", "L4M5", "EE"],
    "M3": ["M3I", "L3R", "L3L", "M4E", "M4I", "L4M5", "EE"],
    "M4": ["M4I", "L4M5", "EE"],
    "M5": ["EE"],
}
MOTORS = ("M1", "M2", "M3", "M4", "M5")
QUARTERS = np.linspace(0.0, math.pi / 2, 3)
# the pose grids (M2 slowest, as FMBPOSE): robot_rigid_grid.dat's, M1 and M4 at 30°,
# M2 × M3 ∈ {0°, 45°, 90°}², M5 at 0; and the coarse grid of the flexible robot in
# tests/fmb_robot.rs (robot_grid.dat with 3 × 3 poses: M1 = M4 = M5 = 0)
GRIDS = {
    "rigid_grid": [(math.radians(30.0), a, b, math.radians(30.0), 0.0)
                   for a, b in itertools.product(QUARTERS, repeat=2)],
    "flexible_grid": [(0.0, a, b, 0.0, 0.0) for a, b in itertools.product(QUARTERS, repeat=2)],
}


def rotation(axis: np.ndarray, angle: float) -> np.ndarray:
    """Rodrigues' rotation matrix about the unit ``axis``."""
    k = np.array([[0.0, -axis[2], axis[1]], [axis[2], 0.0, -axis[0]],
                  [-axis[1], axis[0], 0.0]])
    return np.eye(3) + math.sin(angle) * k + (1.0 - math.cos(angle)) * k @ k


def posed(point: np.ndarray, body: str, pose, axes) -> np.ndarray:
    """``point`` of ``body`` carried from the reference configuration to ``pose``."""
    x = point.copy()
    for motor, angle in reversed(list(zip(MOTORS, pose))):
        if body in BEYOND[motor]:
            p, n = axes[motor]
            x = p + rotation(n, angle) @ (x - p)
    return x


def axes_at(pose, axes) -> dict:
    """Each motor's axis point and direction at ``pose`` (moved by the motors before it)."""
    out = {}
    for k, motor in enumerate(MOTORS):
        p, n = axes[motor]
        for inner, angle in reversed(list(zip(MOTORS[:k], pose[:k]))):
            q, m = axes[inner]
            r = rotation(m, angle)
            p, n = q + r @ (p - q), r @ n
        out[motor] = (p, n)
    return out


def statics(pose, bodies: dict, axes: dict, ee: np.ndarray) -> dict:
    cg = {name: posed(np.array(b["cg"]), name, pose, axes) for name, b in bodies.items()}
    weight = np.array([0.0, 0.0, -G])
    moved = axes_at(pose, axes)
    torques = []
    for motor in MOTORS[:4]:
        p, n = moved[motor]
        moment = sum(np.cross(cg[i] - p, bodies[i]["mass"] * weight) for i in BEYOND[motor])
        torques.append(-float(n @ moment))
    first_moment = sum(bodies[i]["mass"] * (cg[i][0] + cg[i][1]) for i in bodies)
    x_ee = posed(ee, "EE", pose, axes)
    return {"pose": list(pose), "T": torques, "RZ1": -G * first_moment / (2 * HALF_SIDE),
            "ee": x_ee.tolist()}


def main() -> None:
    ref = REPO / "reference" / "robot"
    props = json.loads((ref / "mass_properties.json").read_text())
    bodies = props["bodies"]
    axes = {m: (np.array(props["axis_point"][m]), np.array(props["axis_dir"][m]))
            for m in MOTORS}
    doc = {"provenance": PROVENANCE,
           "input": "reference/robot/mass_properties.json (tools/robot/model.py)",
           "what": "rigid Robolink chain: static holding torques T1-T4 [N m] of M1-M4, "
                   "vertical reaction RZ1 [N] of the plate's spherical corner, EE centre [m], "
                   "per pose (M1..M5 in rad, the FMBPOSE order: M2 slowest); rigid_grid: "
                   "decks/robot/fmb/robot_rigid_grid.dat; flexible_grid: the poses of the "
                   "flexible robot's 3 x 3 grid in tests/fmb_robot.rs; trajectory1_window: "
                   "the EE centre of the rigid chain at the drive targets of trajectory #1 "
                   "(decks/robot/fmb/trajectory1.csv), every 10 ms over the first 0.8 s",
           "total_mass": sum(b["mass"] for b in bodies.values()),
           "table_4_4_total": sum(props["table_4_4"].values()) + 13.05 + 0.93
           + 2 * 0.58 + 2 * 0.36}
    for name, grid in GRIDS.items():
        doc[name] = [statics(p, bodies, axes, np.array(props["ee_centre"])) for p in grid]
    table = np.loadtxt(REPO / "decks" / "robot" / "fmb" / "trajectory1.csv", delimiter=",",
                       skiprows=1)
    start, end, step = WINDOW
    times = np.arange(round((end - start) / step) + 1) * step + start
    rows = [table[np.argmin(np.abs(table[:, 0] - t))] for t in times]
    doc["trajectory1_window"] = {
        "time": times.tolist(),
        "ee": [posed(np.array(props["ee_centre"]), "EE", r[1:], axes).tolist() for r in rows]}
    (ref / "rigid_chain.json").write_text(json.dumps(doc, indent=1) + "\n")
    for r in doc["rigid_grid"]:
        print(np.round(np.degrees(r["pose"][1:3])), np.round(r["T"], 4), round(r["RZ1"], 4))
    print("total mass", doc["total_mass"], "Table 4.4", doc["table_4_4_total"])


if __name__ == "__main__":
    main()
