#!/usr/bin/env python3
"""The rigid four-bar of thesis §4.4 in Exudyn: an independent multibody code as the peer of
paraflex's `SOL FMB` (the rigid four-bar of tests/fourbar.rs, `rigid_deck`).

Model (the same as decks/fourbar/fmb/fourbar_steel.dat with each link rigid):
- links IC, C, OC as planar rigid bodies (Exudyn ObjectRigidBody2D, node at the centre of mass)
  with the mass, centre of mass and inertia I_zz of the reference-steel FE model of each link
  (decks/fourbar/{crank,coupler,output_crank}_free.dat; pyNastran's mass_properties, shells
  of 2 mm at 7990 kg/m³), joints at the link ends (x = 0 and x = L in the link frame);
- ground link 0.25 m; joints A (0, 0) ground–IC, B IC–C, C C–OC, D (0.25, 0) OC–ground as
  RevoluteJoint2D (planar: 9 coordinates, 8 constraints, no redundancy); the initial pose
  closes the loop with IC at 90°;
- drive: the crank's rotation prescribed by a CoordinateConstraint whose offset is the closed
  form θ = 20°·(1 − |2t − 1|)·sin 2π·10t that decks/fourbar/fmb/drive.csv samples every
  0.25 ms (an index-3 constraint on the piecewise-linear table has unbounded accelerations at
  its knots, and Exudyn's multipliers blow up once the step is below the table's spacing);
  gravity 9.81 m/s² along −y (LoadMassProportional);
- integrator: Exudyn's implicit generalized-α (index 3, Newton with its Jacobian), spectral
  radius RHO_INF, step DT over T_END.

Writes reference/exudyn/fourbar_rigid.json: the histories of the drive torque (minus the
constraint's Lagrange multiplier, which Exudyn reports as the reaction on the crank's
coordinate: the torque the drive applies to IC about +z, as paraflex's JTORQ) and the position of the coupler joint C, with provenance (Exudyn version, settings, mass
properties, wall time of Exudyn's solve).

Needs Exudyn, which the project venv carries only for this generator:
    make reference-exudyn          # pip install -r tools/exudyn/requirements.txt, then this script
"""
from __future__ import annotations

import argparse
import json
import math
import time
from importlib.metadata import version
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[2]
OUT = ROOT / "reference/exudyn/fourbar_rigid.json"
GRAVITY = 9.81
GROUND = 0.25
LINKS = [("IC", "crank", 0.100), ("C", "coupler", 0.350), ("OC", "output_crank", 0.300)]
DT, T_END, RHO_INF = 6.25e-5, 0.2, 0.9
EVERY = 16  # one stored sample per millisecond


def mass_properties(link: str) -> dict:
    """Mass, centre of mass (link frame) and I_zz about it of the link's FE model."""
    from pyNastran.bdf.bdf import BDF
    from pyNastran.bdf.mesh_utils.mass_properties import mass_properties as props

    model = BDF(debug=None)
    model.read_bdf(str(ROOT / f"decks/fourbar/{link}_free.dat"))
    mass, cg, inertia = props(model)  # inertia about the centre of mass
    return {"mass": float(mass), "cg": [float(cg[0]), float(cg[1])], "izz": float(inertia[2])}


def pose() -> list[tuple[np.ndarray, float]]:
    """Start point and angle of IC, C, OC closing the loop with IC at 90° (C above the ground)."""
    b = np.array([0.0, LINKS[0][2]])
    d = np.array([GROUND, 0.0])
    lc, lo = LINKS[1][2], LINKS[2][2]
    dist = np.linalg.norm(d - b)
    a = (lc**2 - lo**2 + dist**2) / (2 * dist)
    h = math.sqrt(lc**2 - a**2)
    u = (d - b) / dist
    c = b + a * u + h * np.array([-u[1], u[0]])
    return [
        (np.zeros(2), math.pi / 2),
        (b, math.atan2(*(c - b)[::-1])),
        (d, math.atan2(*(c - d)[::-1])),
    ]


def drive_angle(t: float) -> float:
    """The drive of decks/fourbar/fmb/drive_table.py, θ(t) = 20°·(1 − |2t − 1|)·sin 2π·10t."""
    return math.radians(20.0) * (1.0 - abs(2.0 * t - 1.0)) * math.sin(2.0 * math.pi * 10.0 * t)


def run(dt: float, t_end: float, rho_inf: float) -> dict:
    import exudyn as exu
    from exudyn.itemInterface import (
        CoordinateConstraint, LoadMassProportional, MarkerBodyMass, MarkerBodyPosition,
        MarkerNodeCoordinate, NodePointGround, NodeRigidBody2D, ObjectGround,
        ObjectRigidBody2D, RevoluteJoint2D, SensorBody, SensorObject)

    props = {name: mass_properties(link) for name, link, _ in LINKS}
    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    ground = mbs.AddObject(ObjectGround())
    bodies = []
    for (name, _, length), (start, angle) in zip(LINKS, pose()):
        p = props[name]
        rot = np.array([[math.cos(angle), -math.sin(angle)], [math.sin(angle), math.cos(angle)]])
        centre = start + rot @ np.array(p["cg"])
        node = mbs.AddNode(NodeRigidBody2D(referenceCoordinates=[*centre, angle]))
        body = mbs.AddObject(ObjectRigidBody2D(nodeNumber=node, mass=p["mass"],
                                               inertia=p["izz"]))
        ends = [mbs.AddMarker(MarkerBodyPosition(bodyNumber=body,
                                                 localPosition=[x - p["cg"][0], -p["cg"][1], 0.0]))
                for x in (0.0, length)]
        mass_marker = mbs.AddMarker(MarkerBodyMass(bodyNumber=body))
        mbs.AddLoad(LoadMassProportional(markerNumber=mass_marker, loadVector=[0.0, -GRAVITY, 0.0]))
        bodies.append((node, body, ends))
    (ic_node, _, ic), (_, c_body, c), (_, _, oc) = bodies
    pin = lambda x: mbs.AddMarker(MarkerBodyPosition(bodyNumber=ground, localPosition=[x, 0.0, 0.0]))
    for pair in ([pin(0.0), ic[0]], [ic[1], c[0]], [c[1], oc[1]], [pin(GROUND), oc[0]]):
        mbs.AddObject(RevoluteJoint2D(markerNumbers=pair))
    ground_node = mbs.AddNode(NodePointGround())
    drive = mbs.AddObject(CoordinateConstraint(
        markerNumbers=[mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=ground_node, coordinate=0)),
                       mbs.AddMarker(MarkerNodeCoordinate(nodeNumber=ic_node, coordinate=2))],
        offsetUserFunction=lambda mbs, t, item, offset: drive_angle(t)))
    torque = mbs.AddSensor(SensorObject(objectNumber=drive, storeInternal=True,
                                        outputVariableType=exu.OutputVariableType.Force))
    joint_c = mbs.AddSensor(SensorBody(bodyNumber=c_body, storeInternal=True,
                                       localPosition=[LINKS[1][2] - props["C"]["cg"][0], -props["C"]["cg"][1], 0.0],
                                       outputVariableType=exu.OutputVariableType.Position))
    mbs.Assemble()
    s = exu.SimulationSettings()
    steps = round(t_end / dt)
    s.timeIntegration.numberOfSteps = steps
    s.timeIntegration.endTime = t_end
    s.timeIntegration.generalizedAlpha.spectralRadius = rho_inf
    s.timeIntegration.newton.relativeTolerance = 1e-10
    s.timeIntegration.newton.absoluteTolerance = 1e-12
    s.timeIntegration.verboseMode = 0
    s.solution.file.write = False
    s.solution.sensors.writePeriod = dt
    wall = time.perf_counter()
    mbs.SolveDynamic(s, solverType=exu.DynamicSolverType.GeneralizedAlpha)
    wall = time.perf_counter() - wall
    tq = mbs.GetSensorStoredData(torque)
    pos = mbs.GetSensorStoredData(joint_c)
    keep = slice(0, None, EVERY)
    return {"props": props, "wall": wall, "time": tq[keep, 0], "torque": -tq[keep, 1],
            "cx": pos[keep, 1], "cy": pos[keep, 2], "steps": steps}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--out", type=Path, default=OUT)
    ap.add_argument("--dt", type=float, default=DT)
    args = ap.parse_args()
    r = run(args.dt, T_END, RHO_INF)
    print(f"Exudyn {version('exudyn')}: rigid four-bar, {r['steps']} steps of {args.dt:g} s, "
          f"wall {r['wall']:.3f} s")
    out = {
        "case": "fourbar_rigid",
        "test": "tests/fourbar.rs (rigid_four_bar_matches_exudyn)",
        "provenance": {
            "code": f"Exudyn {version('exudyn')} (PyPI wheel), tools/exudyn/fourbar.py",
            "model": "ObjectRigidBody2D x 3, RevoluteJoint2D x 4, CoordinateConstraint drive "
                     "(offset: the closed form of drive_table.py), LoadMassProportional gravity",
            "integrator": f"generalized-alpha (index 3), spectral radius {RHO_INF}, "
                          f"dt {args.dt:g} s, {r['steps']} steps, Newton rel. tol 1e-10",
            "mass_properties": "pyNastran mass_properties of decks/fourbar/*_free.dat",
            "wall_time_s": round(r["wall"], 3),
        },
        "units": "SI; torque N m about +z on IC; position m (global)",
        "mass_properties": r["props"],
        "time": r["time"].tolist(),
        "torque": r["torque"].tolist(),
        "cx": r["cx"].tolist(),
        "cy": r["cy"].tolist(),
    }
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(out, indent=1) + "\n")
    print(args.out)


if __name__ == "__main__":
    main()
