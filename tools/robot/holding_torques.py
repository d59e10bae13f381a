"""Static holding torques of the rigid Robolink chain, computed here without paraflex: the
reference of ``tests/fmb_robot.rs`` for ``decks/robot/fmb/robot_rigid_grid.dat``.

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
centre of mass.

Run: ``.venv/bin/python tools/robot/holding_torques.py`` (writes
``reference/robot/rigid_holding_torques.json``).
"""
from __future__ import annotations

import itertools
import json
import math
from pathlib import Path

import numpy as np

REPO = Path(__file__).resolve().parents[2]
PROVENANCE = "tools/robot/holding_torques.py"
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
# the pose grid of robot_rigid_grid.dat: M1 and M4 at 30°, M2 × M3 ∈ {0°, 45°, 90°}², M5 at 0
GRID = [(math.radians(30.0), a, b, math.radians(30.0), 0.0)
        for a, b in itertools.product(np.linspace(0.0, math.pi / 2, 3), repeat=2)]


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
    rows = [statics(p, bodies, axes, np.array(props["ee_centre"])) for p in GRID]
    doc = {"provenance": PROVENANCE,
           "input": "reference/robot/mass_properties.json (tools/robot/model.py)",
           "deck": "decks/robot/fmb/robot_rigid_grid.dat",
           "what": "rigid Robolink, rigid drives: static holding torques T1-T4 [N m] of M1-M4, "
                   "vertical reaction RZ1 [N] of the plate's spherical corner, EE centre [m], "
                   "per pose (M1..M5 in rad, the FMBPOSE order: M2 slowest)",
           "total_mass": sum(b["mass"] for b in bodies.values()),
           "poses": rows}
    (ref / "rigid_holding_torques.json").write_text(json.dumps(doc, indent=1) + "\n")
    for r in rows:
        print(np.round(np.degrees(r["pose"][1:3])), np.round(r["T"], 4), round(r["RZ1"], 4))


if __name__ == "__main__":
    main()
