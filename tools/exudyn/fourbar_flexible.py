#!/usr/bin/env python3
"""The flexible steel four-bar of thesis §4.4 in Exudyn: ObjectFFRFreducedOrder links fed with
paraflex's reduced bases, the independent multibody peer of `SOL FMB` on
decks/fourbar/fmb/fourbar_steel.dat (tests/fourbar.rs, `flexible_four_bar_matches_exudyn`).

Route: Exudyn's reduced-order FFRF body (Zwölfer & Gerstmayr's nodal-based FFRF with modal
reduction) needs the mode basis at every mesh node (3 translations per node) and a nodal mass
matrix, from which it computes its own inertia terms. The link artifacts are therefore built
here from the pROM decks with a `DISPLACEMENT = ALL` request, which makes `SOL PROM` write the
basis rows of every grid (`/prom/basis/{grids, rows}`); the mass Exudyn integrates over is the
artifact's nodal masses (`/prom/nodal_mass`, the row-sum lumping paraflex's own invariants of
eq. 4.1–4.3 and A.11–A.19 use). Both are evaluated at the deck's point (the reference steel,
the PMPARs' nominal values). Per link:
- `FEMinterface` with the grid positions, the translation rows Ψ (3 per grid) and the diagonal
  nodal mass matrix; `ObjectFFRFreducedOrderInterface` computes from them the body's mass,
  centre of mass, inertia and the modal inertia terms (its Ψ̃ᵀMΨ, Φ_tᵀMΨ, x̃ᵀMΨ, … — the
  appendix-A invariants computed a second time, independently); the generator checks them
  against the artifact's invariants at p (provenance `invariants_check`);
- the reduced stiffness, mass and Rayleigh damping of the flexible coordinates are the pROM's
  K_r(p), M_r(p), C_r = α M_r + β K_r, as paraflex's M_ff, K_ff, C_ff (M_r is the consistent
  shell mass with rotary inertia; Exudyn's own ΨᵀMΨ from the nodal masses differs from it by
  `mff_lumped_vs_prom` of the provenance, and is not used);
- rigid-body node with Euler parameters at the origin and orientation of the deck's CORD2R.

Joints: Exudyn nodes carry no rotations, so a joint frame is a MarkerSuperElementRigid on the
pin-hole nodes that the RBE2 of meshes/fourbar/<link>_rbe.bdf ties to the joint master grid
(they move rigidly with the master, so the marker turns as the master grid of paraflex's
joint does); the four revolutes about z are GenericJoints with axes 0-4 locked (as paraflex's
REV: coincident points, parallel z axes; redundant for rigid links, taken by the flexibility).
The drive locks axis 5 of joint A too, with the rotation offset θ(t) of drive_table.py in
closed form (fourbar.py says why not the table). Gravity 9.81 m/s² along −y.
Integrator: Exudyn's implicit generalized-α (index 3), spectral radius RHO_INF, step DT.

Outputs, one sample per millisecond: drive torque (the joint's reaction about z), the
position of the coupler joint C (its master grid), the deviation of C from the rigid twin
(Exudyn's rigid four-bar of fourbar.py at the same step: ‖x_C − x_C,rigid‖, eq. 4.10) and the
coupler's mid-span strain gauge MIDX (the artifact's sensor row H_r times Exudyn's modal
coordinates). Writes reference/exudyn/fourbar_flexible.json with provenance.

Needs Exudyn (the venv carries it only for this generator) and a paraflex binary:
    make reference-exudyn
"""
from __future__ import annotations

import argparse
import json
import math
import sys
import tempfile
import time
from importlib.metadata import version
from pathlib import Path

import h5py
import numpy as np

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools"))
sys.path.insert(0, str(Path(__file__).resolve().parent))

import fourbar  # noqa: E402  (the rigid twin and the drive)
from paraflex_tools.prom import Prom  # noqa: E402
from paraflex_tools.runner import find_binary, run_checked  # noqa: E402

OUT = ROOT / "reference/exudyn/fourbar_flexible.json"
DECKS = ROOT / "decks/fourbar/fmb"
GRAVITY = 9.81
#: name, link (its pROM deck and mesh); points A and C (in the xz plane) of the CORD2R of
#: fourbar_steel.dat that places the link's artifact
LINKS = [
    ("IC", "crank", (0.0, 0.0), (0.0, 1.0)),
    ("C", "coupler", (0.0, 0.1), (0.82566454862, 0.66416137155)),
    ("OC", "output_crank", (0.25, 0.0), (0.37994197339, 0.99152160014)),
]
MASTERS = (1000001, 1000002)
DT, T_END, RHO_INF = 2.5e-5, 0.2, 0.9
GAUGE = "MIDX"


def build_artifacts(paraflex: Path, work: Path) -> dict[str, Path]:
    """Runs each link's pROM deck with `DISPLACEMENT = ALL` (every grid's basis rows)."""
    out = {}
    for _, link, *_ in LINKS:
        text = (DECKS / f"{link}_prom.dat").read_text()
        text = text.replace("'../../../meshes/", f"'{ROOT / 'meshes'}/")
        text = text.replace("PROM = 1\n", "PROM = 1\nDISPLACEMENT = ALL\n", 1)
        deck = work / f"{link}_prom.dat"
        deck.write_text(text)
        out[link] = work / f"{link}.h5"
        run_checked(deck, out[link], paraflex)
    return out


def pin_holes(link: str) -> dict[int, list[int]]:
    """The grids each RBE2 of the link's mesh ties to its master grid."""
    holes, current = {}, None
    for line in (ROOT / f"meshes/fourbar/{link}_rbe.bdf").read_text().splitlines():
        fields = [line[i:i + 8].strip() for i in range(0, len(line), 8)]
        if fields[0] == "RBE2":
            current = holes.setdefault(int(fields[2]), [])
            current.extend(int(f) for f in fields[4:] if f)
        elif fields[0] == "" and current is not None:
            current.extend(int(f) for f in fields[1:] if f)
        else:
            current = None
    return holes


def link_data(path: Path) -> dict:
    """The artifact at its nominal point: reduced matrices, every grid's translation rows,
    nodal masses and positions, the invariants paraflex stored, the gauge row."""
    prom = Prom(path)
    f_p = prom.coefficients()
    stiffness, mass, _ = prom.matrices()
    with h5py.File(path, "r") as h5:
        g = h5["prom"]
        grids = g["basis/grids"][()]
        rows = g["basis/rows"][()]
        assert np.array_equal(grids, g["nodal_mass/grids"][()])
        nodal = sum(f * g[f"nodal_mass/{i}"][()] for i, f in enumerate(f_p))
        invariants = {k: sum(f * g[f"invariants/{k}/{i}"][()] for i, f in enumerate(f_p))
                      for k in (0, 1, 2, 3, 6)}
        positions = g["nodal_mass/positions"][()]
    return {"K": stiffness, "M": mass, "alpha": prom.alpha, "beta": prom.beta,
            "grids": list(grids), "psi": rows[:, :3, :].reshape(-1, rows.shape[2]),
            "nodal": nodal, "positions": positions, "invariants": invariants,
            "gauge": prom.sensor_rows[prom.sensor_names.index(GAUGE)]}


def ffrf_interface(data: dict):
    """Exudyn's reduced-order FFRF data of one link (its own inertia terms, the pROM's
    flexible-coordinate matrices), with the checks against paraflex's invariants."""
    import scipy.sparse as sp
    from exudyn.FEM import FEMinterface, ObjectFFRFreducedOrderInterface

    n = len(data["grids"])
    fem = FEMinterface()
    fem.nodes = {"Position": data["positions"]}
    fem.massMatrix = sp.csr_matrix(sp.diags(np.repeat(data["nodal"], 3)))
    fem.stiffnessMatrix = sp.csr_matrix((3 * n, 3 * n))
    fem.modeBasis = {"matrix": data["psi"], "type": "NormalModes"}
    cms = ObjectFFRFreducedOrderInterface(fem)
    lumped = cms.massMatrixReduced
    cms.massMatrixReduced = data["M"]
    cms.stiffnessMatrixReduced = data["K"]
    inv = data["invariants"]
    m = data["nodal"]
    r = np.linalg.norm(data["positions"], axis=1)
    psi = np.abs(data["psi"]).reshape(n, 3, -1)
    # each difference against the size of the sum's terms (round-off of the same sum)
    scale = {1: np.sum(m * r), 2: np.sum(m[:, None, None] * psi, axis=0).max(),
             3: np.sum(m * r * r), 6: np.sum((m * r)[:, None, None] * psi, axis=0).max()}
    diff = lambda a, k: float(np.abs(np.ravel(a) - np.ravel(inv[k])).max() / scale[k])
    checks = {
        "mass (m)": abs(cms.totalMass - inv[0].item()) / inv[0].item(),
        "M1 (sum m r)": diff(cms.totalMass * cms.chiU, 1),
        "M2 (Phi_t^T M Psi)": diff(cms.mPhitTPsi, 2),
        "M3 (-inertiaLocal)": diff(-cms.inertiaLocal, 3),
        "M6 (mXRefTildePsi)": diff(cms.mXRefTildePsi, 6),
        "M_ff lumped vs pROM": float(np.abs(lumped - data["M"]).max() / np.abs(data["M"]).max()),
    }
    return cms, checks


def rotation_z(x_axis) -> np.ndarray:
    c, s = np.asarray(x_axis) / np.linalg.norm(x_axis)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def run(artifacts: dict[str, Path], dt: float, t_end: float, rho_inf: float) -> dict:
    import exudyn as exu
    from exudyn.itemInterface import (MarkerBodyRigid, MarkerSuperElementPosition,
                                      MarkerSuperElementRigid, ObjectGround, ObjectJointGeneric,
                                      SensorMarker, SensorNode, SensorObject)

    sc = exu.SystemContainer()
    mbs = sc.AddSystem()
    ground = mbs.AddObject(ObjectGround())
    bodies, checks, sizes = [], {}, {}
    for name, link, origin, x_point in LINKS:
        data = link_data(artifacts[link])
        cms, checks[name] = ffrf_interface(data)
        sizes[name] = {"grids": len(data["grids"]), "modes": int(data["K"].shape[0])}
        rot = rotation_z(np.subtract(x_point, origin))
        added = cms.AddObjectFFRFreducedOrder(
            mbs, positionRef=[*origin, 0.0], rotationMatrixRef=rot,
            massProportionalDamping=data["alpha"], stiffnessProportionalDamping=data["beta"],
            gravity=[0.0, -GRAVITY, 0.0])
        body = added["oFFRFreducedOrder"]
        index = {g: i for i, g in enumerate(data["grids"])}
        frames = []
        for master, ring in sorted(pin_holes(link).items()):
            nodes = [index[g] for g in ring]
            centre = data["positions"][nodes].mean(axis=0)
            frames.append(mbs.AddMarker(MarkerSuperElementRigid(
                bodyNumber=body, meshNodeNumbers=nodes, weightingFactors=[1 / len(nodes)] * len(nodes),
                offset=list(data["positions"][index[master]] - centre))))
        point_c = mbs.AddMarker(MarkerSuperElementPosition(
            bodyNumber=body, meshNodeNumbers=[index[MASTERS[1]]], weightingFactors=[1.0]))
        bodies.append({"frames": frames, "rot": rot, "point_c": point_c, "data": data,
                       "modal": added["nGenericODE2"]})
    ic, c, oc = bodies

    def fixed(x, rot):
        return mbs.AddMarker(MarkerBodyRigid(bodyNumber=ground, localHT=exu.HT(
            rotation=rot, translation=[x, 0.0, 0.0])))

    revolute = [1, 1, 1, 1, 1, 0]
    drive = mbs.AddObject(ObjectJointGeneric(
        markerNumbers=[fixed(0.0, ic["rot"]), ic["frames"][0]], constrainedAxes=[1] * 6,
        offsetUserFunction=lambda mbs, t, item, par: [0, 0, 0, 0, 0, fourbar.drive_angle(t)]))
    # B: IC end – C start; C: C end – OC end; D: OC start – ground (marker 0 of each joint in
    # the frame of the first link, so that the locked axes are its z and the joint's initial
    # relative rotation is the links' angle about z, free)
    for pair in ([ic["frames"][1], c["frames"][0]], [c["frames"][1], oc["frames"][1]],
                 [fixed(fourbar.GROUND, np.eye(3)), oc["frames"][0]]):
        mbs.AddObject(ObjectJointGeneric(markerNumbers=pair, constrainedAxes=revolute))
    torque = mbs.AddSensor(SensorObject(objectNumber=drive, storeInternal=True,
                                        outputVariableType=exu.OutputVariableType.TorqueLocal))
    joint_c = mbs.AddSensor(SensorMarker(markerNumber=c["point_c"], storeInternal=True,
                                         outputVariableType=exu.OutputVariableType.Position))
    modal = mbs.AddSensor(SensorNode(nodeNumber=c["modal"], storeInternal=True,
                                     outputVariableType=exu.OutputVariableType.Coordinates))
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
    wall, cpu = time.perf_counter(), time.process_time()
    mbs.SolveDynamic(s, solverType=exu.DynamicSolverType.GeneralizedAlpha)
    wall, cpu = time.perf_counter() - wall, time.process_time() - cpu
    every = round(1e-3 / dt)
    keep = slice(0, None, every)
    tq = mbs.GetSensorStoredData(torque)[keep]
    pos = mbs.GetSensorStoredData(joint_c)[keep]
    q = mbs.GetSensorStoredData(modal)[keep, 1:]
    return {"wall": wall, "cpu": cpu, "steps": steps, "time": tq[:, 0], "torque": tq[:, 3],
            "cx": pos[:, 1], "cy": pos[:, 2], "strain_c": q @ c["data"]["gauge"],
            "checks": checks, "sizes": sizes, "unknowns": {"ode2": len(mbs.systemData.GetODE2Coordinates()),
                         "algebraic": len(mbs.systemData.GetAECoordinates())}}


def rigid_twin(dt: float, t_end: float, rho_inf: float) -> dict:
    """fourbar.py's rigid four-bar at the same step, one sample per millisecond."""
    fourbar.EVERY = round(1e-3 / dt)
    return fourbar.run(dt, t_end, rho_inf)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("-o", "--out", type=Path, default=OUT)
    ap.add_argument("--paraflex", default=None,
                    help="paraflex binary that builds the artifacts (default: the release build)")
    ap.add_argument("--dt", type=float, default=DT)
    ap.add_argument("--t-end", type=float, default=T_END)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as work:
        artifacts = build_artifacts(find_binary(args.paraflex), Path(work))
        r = run(artifacts, args.dt, args.t_end, RHO_INF)
    twin = rigid_twin(args.dt, args.t_end, RHO_INF)
    deviation = np.hypot(r["cx"] - twin["cx"], r["cy"] - twin["cy"])
    print(f"Exudyn {version('exudyn')}: flexible four-bar, {r['unknowns']} unknowns, "
          f"{r['steps']} steps of {args.dt:g} s, wall {r['wall']:.2f} s, CPU {r['cpu']:.2f} s")
    print("invariant checks:", json.dumps(r["checks"]))
    out = {
        "case": "fourbar_flexible",
        "test": "tests/fourbar.rs (flexible_four_bar_matches_exudyn)",
        "provenance": {
            "code": f"Exudyn {version('exudyn')} (PyPI wheel), tools/exudyn/fourbar_flexible.py",
            "model": "ObjectFFRFreducedOrder x 3 (FEMinterface: every grid's translation rows "
                     "of the link artifacts built with DISPLACEMENT = ALL, nodal masses; "
                     "K_r, M_r, Rayleigh C_r of the pROMs at the nominal steel), "
                     "MarkerSuperElementRigid on the RBE2 pin holes, ObjectJointGeneric revolutes "
                     "about z, drive: joint A's z rotation offset (closed form of drive_table.py), "
                     "LoadMassProportional gravity",
            "integrator": f"generalized-alpha (index 3), spectral radius {RHO_INF}, "
                          f"dt {args.dt:g} s, {r['steps']} steps, Newton rel. tol 1e-10",
            "unknowns": r["unknowns"],
            "bodies": r["sizes"],
            "invariants_check": r["checks"],
            "wall_time_s": round(r["wall"], 3),
            "cpu_time_s": round(r["cpu"], 3),
            "rigid_twin": "tools/exudyn/fourbar.py at the same step and spectral radius",
        },
        "units": "SI; torque N m about +z on IC; position m (global); strain of the coupler's MIDX gauge",
        "time": r["time"].tolist(),
        "torque": r["torque"].tolist(),
        "cx": r["cx"].tolist(),
        "cy": r["cy"].tolist(),
        "deviation": deviation.tolist(),
        "strain_c": r["strain_c"].tolist(),
        "rigid_torque": twin["torque"].tolist(),
    }
    args.out.parent.mkdir(parents=True, exist_ok=True)
    args.out.write_text(json.dumps(out, indent=1) + "\n")
    print(args.out)


if __name__ == "__main__":
    main()
