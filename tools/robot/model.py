"""The Robolink manipulator as a flexible multibody model (thesis §4.5.1, Fig. 4.13–4.18).

Writes the mechanism include of the pFMB, ``decks/robot/fmb/robot_bodies.inc`` (flexible
plate and links from the pROM artifacts of ``decks/robot/fmb/*_prom.dat``), its rigid-link
variant ``decks/robot/fmb/robot_rigid_bodies.inc`` (every link a RIGIDB with its FE model's
mass properties) and ``reference/robot/mass_properties.json`` (every body's mass, centre of
mass and inertia, and the joint positions, for the independent checks of
``tools/robot/rigid_chain.py``).

Rigid bodies (thesis: "motors, gearboxes and gripper are modeled as rigid bodies with uniform
density", their inertia from the CAD with the density that gives the weighed mass of Table 4.4):
each is a representative solid built and tetrahedral-meshed with gmsh; its volume, centre of
mass and inertia are integrated exactly over the linear tetrahedra and the uniform density is
the Table 4.4 mass over the meshed volume. The solids (reference configuration: the arm
upright, z up, the pitch axes of M2–M4 along y, global gravity along −z as in §4.5.3):

* motor Mi: a cylinder of radius R and length H on its axis, split into the internal part
  Mii (the core r < R/2: rotor, gearbox output and flange) and the external part Mie (the
  housing R/2 < r < R), one density per motor, so Mii carries 1/4 of the motor's mass;
* L4 + M5: a box 70 × 70 × 140 mm along the arm above M4 (plastic link and wrist motor);
* EE: a box 80 × 40 × 100 mm (the gripper) above M5; its centre is the EE sensor point.

Flexible links: the pROMs of meshes/robot.py's meshes. L2r/L2l and L3r/L3l are the same FE
model placed twice, the joggle of each side bent inwards; the L2 sides sit outside L1's
uprights, the L3 sides outside the L2 sides' distal ends.

Run: ``.venv/bin/python tools/robot/model.py`` (about 10 s).
"""
from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import gmsh
import numpy as np

from paraflex_tools.cards import card
from paraflex_tools.meshing import gmsh_session

PROVENANCE = "tools/robot/model.py"
REPO = Path(__file__).resolve().parents[2]
OUT = REPO / "decks" / "robot" / "fmb"
MESHES = REPO / "meshes" / "robot"

# Table 4.4 masses [kg]
MASS = {"M1": 6.00, "M2": 4.35, "M3": 1.84, "M4": 0.83, "L4M5": 0.82, "EE": 0.63}
# Table 4.7 joint stiffness [N m/rad] and damping [N m s/rad]
DRIVE_KC = {"M1": (2000.0, 20.0), "M2": (16000.0, 500.0), "M3": (8000.0, 50.0),
            "M4": (8000.0, 50.0)}
# Motor cylinders (radius, length) [m]: our choice, sized to the link ends they sit between
MOTOR = {"M1": (0.055, 0.12), "M2": (0.045, 0.10), "M3": (0.038, 0.09), "M4": (0.030, 0.09)}
CORE = 0.5                      # internal part: the core r < CORE · R

# Link interface masters (meshes/robot/*_rbe.bdf, in each mesh's own system)
L1_TOP = 0.16                   # M2 axis above L1's base
L2_B = np.array([0.418649341181297, 0.0, 0.015])
L3_B = np.array([0.309776674387658, 0.0, 0.01])
# Lateral position |y| of each side's proximal end (the joggle brings the distal end inwards)
L2_Y = 0.070
L3_Y = 0.065

# Reference configuration (arm upright): heights of the axes
Z_L1 = MOTOR["M1"][1]           # L1 base on top of M1
Z_M2 = Z_L1 + L1_TOP
Z_M3 = Z_M2 + L2_B[0]
Z_M4 = Z_M3 + L3_B[0]
L4_BOX = (0.07, 0.07, 0.14)
L4_GAP = 0.035                  # L4 box starts this far above the M4 axis
Z_M5 = Z_M4 + L4_GAP + L4_BOX[2]
EE_BOX = (0.08, 0.04, 0.10)
EE_CENTRE = np.array([0.0, 0.0, Z_M5 + EE_BOX[2] / 2])
PLATE_CORNERS = (1, 2, 3)       # corner grids (-x -y, +x -y, -x +y) of meshes/robot/base_plate.bdf
MASTER_A, MASTER_B = 1000001, 1000002


@dataclass
class MassProperties:
    """Mass, centre of mass and inertia about it (global axes)."""

    mass: float
    cg: np.ndarray
    inertia: np.ndarray

    def as_json(self) -> dict:
        return {"mass": self.mass, "cg": self.cg.tolist(), "inertia": self.inertia.tolist()}


def tetra_integrals(points: np.ndarray, tets: np.ndarray) -> tuple[float, np.ndarray, np.ndarray]:
    """Volume, first moment ∫x dV and second moment ∫x xᵀ dV of a linear tetrahedral mesh
    (exact: ∫x xᵀ = V/20 (Σ_a x_a x_aᵀ + s sᵀ), s = Σ_a x_a)."""
    x = points[tets]                                   # (n, 4, 3)
    vol = np.abs(np.einsum("ij,ij->i", np.cross(x[:, 1] - x[:, 0], x[:, 2] - x[:, 0]),
                           x[:, 3] - x[:, 0])) / 6.0
    s = x.sum(axis=1)
    first = (vol[:, None] * s / 4.0).sum(axis=0)
    second = np.einsum("i,iaj,iak->jk", vol / 20.0, x, x) + np.einsum("i,ij,ik->jk",
                                                                      vol / 20.0, s, s)
    return float(vol.sum()), first, second


def properties(mass: float, volume: float, first: np.ndarray, second: np.ndarray) -> MassProperties:
    """Uniform density mass / volume: centre of mass and inertia about it."""
    rho = mass / volume
    cg = first / volume
    j = rho * second - mass * np.outer(cg, cg)         # ∫ρ (x − c)(x − c)ᵀ dV
    return MassProperties(mass, cg, np.trace(j) * np.eye(3) - j)


def _meshed(build, size: float) -> tuple[np.ndarray, np.ndarray]:
    """Points and linear tetrahedra of the volume(s) ``build()`` adds to the OCC model."""
    with gmsh_session("solid"):
        build(gmsh.model.occ)
        gmsh.model.occ.synchronize()
        gmsh.option.setNumber("Mesh.MeshSizeMax", size)
        gmsh.option.setNumber("Mesh.MeshSizeFromCurvature", 24)
        gmsh.model.mesh.generate(3)
        tags, coords, _ = gmsh.model.mesh.getNodes()
        points = np.zeros((int(tags.max()) + 1, 3))
        points[tags.astype(int)] = coords.reshape(-1, 3)
        _, node_tags = gmsh.model.mesh.getElementsByType(4)
        return points, node_tags.astype(int).reshape(-1, 4)


def motor(name: str, centre: np.ndarray, axis: np.ndarray) -> tuple[MassProperties, MassProperties]:
    """External (housing) and internal (core) parts of motor ``name``: one uniform density."""
    r, h = MOTOR[name]
    base = centre - axis * h / 2
    d = axis * h

    def core(occ):
        occ.addCylinder(*base, *d, CORE * r)

    def housing(occ):
        outer = occ.addCylinder(*base, *d, r)
        inner = occ.addCylinder(*base, *d, CORE * r)
        occ.cut([(3, outer)], [(3, inner)])

    parts = [tetra_integrals(*_meshed(b, r / 3)) for b in (housing, core)]
    total = sum(p[0] for p in parts)
    rho = MASS[name] / total
    return tuple(properties(rho * v, v, f, s) for v, f, s in parts)


def box(name: str, lower: np.ndarray, size: tuple) -> MassProperties:
    """A uniform box of Table 4.4's mass for body ``name``."""
    v, f, s = tetra_integrals(*_meshed(lambda occ: occ.addBox(*lower, *size), min(size) / 2))
    return properties(MASS[name], v, f, s)


def read_shell_mesh(path: Path) -> tuple[dict, list]:
    """GRIDs (id → xyz) and shell connectivities of a meshes/robot include (free or fixed)."""
    grids, shells = {}, []
    lines = path.read_text().splitlines()
    i = 0
    while i < len(lines):
        line = lines[i]
        if line.startswith("GRID*"):
            nxt = lines[i + 1]
            grids[int(line[8:24])] = np.array([float(line[40:56]), float(line[56:72]),
                                               float(nxt[8:24])])
            i += 2
            continue
        if line.startswith("GRID "):
            f = [line[k:k + 8] for k in range(0, 48, 8)]
            grids[int(f[1])] = np.array([float(v) for v in f[3:6]])
        elif line.startswith(("CQUAD4", "CTRIA3")):
            n = 4 if line.startswith("CQUAD4") else 3
            shells.append([int(line[k:k + 8]) for k in range(24, 24 + 8 * n, 8)])
        i += 1
    return grids, shells


def shell_properties(path: Path, rho: float, t: float, to_global) -> MassProperties:
    """Mass properties of a shell mesh of thickness t (each element split into triangles, its
    mass ρ t A at the triangle's centroid; the sheet's own rotary inertia ρ t³/12 is left out)."""
    grids, shells = read_shell_mesh(path)
    masses, points = [], []
    for nodes in shells:
        x = [to_global(grids[g]) for g in nodes]
        for a, b in ((1, 2), (2, 3))[: len(x) - 2]:
            area = 0.5 * np.linalg.norm(np.cross(x[a] - x[0], x[b] - x[0]))
            masses.append(rho * t * area)
            points.append((x[0] + x[a] + x[b]) / 3)
    m, p = np.array(masses), np.array(points)
    cg = (m[:, None] * p).sum(axis=0) / m.sum()
    d = p - cg
    j = np.einsum("i,ij,ik->jk", m, d, d)
    return MassProperties(float(m.sum()), cg, np.trace(j) * np.eye(3) - j)


@dataclass(frozen=True)
class Placement:
    """A link mesh's basic system in the global one: origin, local x and local z axes."""

    origin: np.ndarray
    ex: np.ndarray
    ez: np.ndarray

    def to_global(self, x: np.ndarray) -> np.ndarray:
        ey = np.cross(self.ez, self.ex)
        return self.origin + x[0] * self.ex + x[1] * ey + x[2] * self.ez

    def cord2r(self, cid: int) -> str:
        b, c = self.origin + self.ez, self.origin + self.ex
        return card("CORD2R", cid, None, *map(float, self.origin), *map(float, b),
                    *map(float, c))


Z, Y, X = np.array([0.0, 0.0, 1.0]), np.array([0.0, 1.0, 0.0]), np.array([1.0, 0.0, 0.0])
# body id, name, artifact, mesh, placement, (density, thickness) of the sheet
LINKS = [
    (1, "P", "plate.h5", "base_plate", Placement(np.zeros(3), X, Z), (2630.0, 0.005)),
    (2, "L1", "l1.h5", "l1", Placement(np.array([0.0, 0.0, Z_L1]), X, Z), (7990.0, 0.002)),
    (3, "L2R", "l2.h5", "l2", Placement(np.array([0.0, -L2_Y, Z_M2]), Z, Y), (7990.0, 0.002)),
    (4, "L2L", "l2.h5", "l2", Placement(np.array([0.0, L2_Y, Z_M2]), Z, -Y), (7990.0, 0.002)),
    (5, "L3R", "l3.h5", "l3", Placement(np.array([0.0, -L3_Y, Z_M3]), Z, Y), (7990.0, 0.002)),
    (6, "L3L", "l3.h5", "l3", Placement(np.array([0.0, L3_Y, Z_M3]), Z, -Y), (7990.0, 0.002)),
]
RIGID_IDS = {"M1E": 11, "M1I": 12, "M2E": 13, "M2I": 14, "M3E": 15, "M3I": 16, "M4E": 17,
             "M4I": 18, "L4M5": 19, "EE": 20}
# drive: (joint id, body, parent, axis, the motor) for M1..M4 (compliant) and M5 (rigid)
AXIS_POINT = {"M1": np.array([0.0, 0.0, Z_L1]), "M2": np.array([0.0, 0.0, Z_M2]),
              "M3": np.array([0.0, 0.0, Z_M3]), "M4": np.array([0.0, 0.0, Z_M4]),
              "M5": np.array([0.0, 0.0, Z_M5])}
AXIS_DIR = {"M1": Z, "M2": Y, "M3": Y, "M4": Y, "M5": Z}


def rigid_bodies() -> dict[str, MassProperties]:
    """Every rigid body's mass properties (global axes, reference configuration)."""
    out = {}
    centres = {"M1": np.array([0.0, 0.0, Z_L1 / 2]), "M2": AXIS_POINT["M2"],
               "M3": AXIS_POINT["M3"], "M4": AXIS_POINT["M4"]}
    for m in ("M1", "M2", "M3", "M4"):
        out[m + "E"], out[m + "I"] = motor(m, centres[m], AXIS_DIR[m])
    lx, ly, _ = L4_BOX
    out["L4M5"] = box("L4M5", np.array([-lx / 2, -ly / 2, Z_M4 + L4_GAP]), L4_BOX)
    ex, ey, _ = EE_BOX
    out["EE"] = box("EE", np.array([-ex / 2, -ey / 2, Z_M5]), EE_BOX)
    return out


def rigidb(bid: int, name: str, p: MassProperties) -> str:
    i = p.inertia
    return card("RIGIDB", bid, name, p.mass, 0, *map(float, p.cg), None,
                i[0, 0], i[1, 0], i[1, 1], i[2, 0], i[2, 1], i[2, 2])


class Mechanism:
    """Cards of the markers and joints, numbered as they are added."""

    def __init__(self, flexible: bool):
        self.flexible = flexible
        self.cards: list[str] = []
        self.marker_id: dict[tuple, int] = {}
        self.joint_id = 0
        self.placement = {name: pl for _, name, _, _, pl, _ in LINKS}
        self.body_id = {name: bid for bid, name, *_ in LINKS} | RIGID_IDS

    def _marker(self, key: tuple, fields: tuple) -> int:
        """The marker of ``key`` = (body, what), added with ``fields`` after its body id when
        new; ids are 100 × body id + 1, 2, … in the order of addition."""
        if key not in self.marker_id:
            body = key[0]
            mid = 100 * self.body_id[body] + sum(k[0] == body for k in self.marker_id) + 1
            self.marker_id[key] = mid
            self.cards.append(card("MARKER", mid, self.body_id[body], *fields))
        return self.marker_id[key]

    def grid_marker(self, body: str, grid: int, position: np.ndarray) -> int:
        """A marker on a link's interface grid (a point marker on the rigid-link variant)."""
        fields = (grid,) if self.flexible else (None, *map(float, position))
        return self._marker((body, grid), fields)

    def point_marker(self, body: str, position: np.ndarray) -> int:
        """A marker at ``position`` on a rigid body."""
        return self._marker((body, tuple(np.round(position, 12))),
                            (None, *map(float, position)))

    def joint(self, kind: str, mk1: int, mk2: int, axis=Z) -> int:
        self.joint_id += 1
        self.cards.append(card("JOINT", self.joint_id, kind, mk1, mk2, *map(float, axis)))
        return self.joint_id

    def link_end(self, link: str, master: int, local: np.ndarray) -> int:
        return self.grid_marker(link, master, self.placement[link].to_global(local))


def link_ends() -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """The local position of each link's masters (their meshes' *_rbe.bdf)."""
    return {"L1": (np.zeros(3), np.array([0.0, 0.0, L1_TOP])), "L2": (np.zeros(3), L2_B),
            "L3": (np.zeros(3), L3_B)}


def mechanism(flexible: bool) -> tuple[list[str], dict]:
    """Markers, joints and drives of the robot; the positions of its joints (for the JSON)."""
    m = Mechanism(flexible)
    ends = link_ends()
    # the plate's frame: three of its corners, 3-2-1 (SPH, INLINE along the edge to the
    # second corner, INPLANE normal to the plate): six independent equations
    corner = {g: x for g, x in read_shell_mesh(MESHES / "base_plate.bdf")[0].items()
              if g in PLATE_CORNERS}
    c1, c2, c3 = PLATE_CORNERS
    m.joint("SPH", m.grid_marker("P", c1, corner[c1]), 0)
    m.joint("INLINE", m.grid_marker("P", c2, corner[c2]), 0, corner[c2] - corner[c1])
    m.joint("INPLANE", m.grid_marker("P", c3, corner[c3]), 0, Z)
    m.joint("FIX", m.point_marker("M1E", np.zeros(3)), m.grid_marker("P", MASTER_A, np.zeros(3)))
    drives = {}

    def motor_joint(name: str, inner: str, outer: str) -> None:
        p = AXIS_POINT[name]
        drives[name] = m.joint("REV", m.point_marker(inner, p), m.point_marker(outer, p),
                               AXIS_DIR[name])

    motor_joint("M1", "M1I", "M1E")
    m.joint("FIX", m.link_end("L1", MASTER_A, ends["L1"][0]), m.point_marker("M1I", AXIS_POINT["M1"]))
    m.joint("FIX", m.point_marker("M2E", AXIS_POINT["M2"]), m.link_end("L1", MASTER_B, ends["L1"][1]))
    # each two-sided link: its motor's joint, both sides bracketed to the motor's internal
    # part and to the next motor's external part (a closed loop per link)
    for motor, link, mot_in, mot_out, nxt in (("M2", "L2", "M2I", "M2E", "M3E"),
                                              ("M3", "L3", "M3I", "M3E", "M4E")):
        motor_joint(motor, mot_in, mot_out)
        for side in ("R", "L"):
            name = link + side
            a = m.placement[name].to_global(ends[link][0])
            b = m.placement[name].to_global(ends[link][1])
            m.joint("FIX", m.link_end(name, MASTER_A, ends[link][0]), m.point_marker(mot_in, a))
            m.joint("FIX", m.point_marker(nxt, b), m.link_end(name, MASTER_B, ends[link][1]))
    motor_joint("M4", "M4I", "M4E")
    m.joint("FIX", m.point_marker("L4M5", AXIS_POINT["M4"]), m.point_marker("M4I", AXIS_POINT["M4"]))
    motor_joint("M5", "EE", "L4M5")
    ee = m.point_marker("EE", EE_CENTRE)
    cards = m.cards
    for k, name in enumerate(("M1", "M2", "M3", "M4", "M5"), start=1):
        if name in DRIVE_KC and flexible:
            kk, c = DRIVE_KC[name]
            cards.append(card("JDRIVE", k, drives[name], k, 1.0, kk, c))
        else:
            cards.append(card("JDRIVE", k, drives[name], k, 1.0))
    info = {"drive_joint": drives, "ee_marker": ee,
            "axis_point": {k: v.tolist() for k, v in AXIS_POINT.items()},
            "axis_dir": {k: v.tolist() for k, v in AXIS_DIR.items()}}
    return cards, info


HEADER = """$ {what}
$ generated by {prov} -- do not edit. Robolink manipulator (thesis sec. 4.5.1, Fig. 4.13-4.18),
$ SI units, reference configuration: the arm upright (z up), pitch axes M2-M4 along y.
$ Bodies: 1 P, 2 L1, 3 L2R, 4 L2L, 5 L3R, 6 L3L {kind}; 11/12 M1E/M1I, 13/14 M2E/M2I,
$ 15/16 M3E/M3I, 17/18 M4E/M4I (external/internal motor parts), 19 L4M5, 20 EE (rigid).
$ Drives: JDRIVE k on motor Mk, table k (relative angle, rad){drives}.
$ Marker {ee} is the EE centre. Gravity: GRAV 1, 9.81 m/s2 along -z.
"""


def include_text(name: str, flexible: bool, rigid: dict, links: dict, artifacts: dict | None = None,
                 prov: str = PROVENANCE) -> tuple[str, dict]:
    """The text of the mechanism include ``name`` (flexible links, or the rigid-link variant) and
    its ids (``info``). ``artifacts`` replaces the pROM artifact of the bodies it names (e.g. the
    composite sides)."""
    cards, info = mechanism(flexible)
    out = [HEADER.format(what=name, prov=prov, ee=info["ee_marker"],
                         drives=": M1-M4 compliant (Table 4.7), M5 rigid" if flexible else "",
                         kind="(flexible, FLEXB of the pROMs beside this file)" if flexible
                         else "(rigid: each link's FE mass properties;\n$ every drive rigid: the rigid chain of the holding-torque check)")]
    out.append(card("GRAV", 1, None, 9.81, 0.0, 0.0, -1.0))
    for bid, name, artifact, _, pl, _ in LINKS:
        if flexible:
            cid = 0 if name == "P" else 10 + bid
            if cid:
                out.append(pl.cord2r(cid))
            artifact = (artifacts or {}).get(name, artifact)
            out.append(card("FLEXB", bid, name, f"'{artifact}'", cid))
        else:
            out.append(rigidb(bid, name, links[name]))
    for name, bid in RIGID_IDS.items():
        out.append(rigidb(bid, name, rigid[name]))
    out += cards
    return "".join(out), info


def write_include(path: Path, flexible: bool, rigid: dict, links: dict) -> dict:
    """Writes the mechanism include (flexible links, or the rigid-link variant); its ids."""
    text, info = include_text(path.name, flexible, rigid, links)
    path.write_text(text)
    return info


def write_sensors(path: Path, info: dict) -> None:
    """The MSENSORs of the robot decks (joint and marker ids of ``info``)."""
    j, ee = info["drive_joint"], info["ee_marker"]
    rows = [("EEX", "POS", None, ee, 1.0, 0.0, 0.0), ("EEY", "POS", None, ee, 0.0, 1.0, 0.0),
            ("EEZ", "POS", None, ee, 0.0, 0.0, 1.0),
            ("EEDEV", "DEV", None, ee), ("EEAZ", "ACCEL", None, ee, 0.0, 0.0, 1.0)]
    rows += [(f"T{k}", "JTORQ", None, j[f"M{k}"]) for k in range(1, 5)]
    rows += [("EPS2", "STRAIN", 3, "GAUGE"), ("EPS3", "STRAIN", 5, "GAUGE")]
    rows += [("RZ1", "JFORCE", None, 1, 0.0, 0.0, 1.0)]
    head = (f"$ robot_sensors.inc: generated by {PROVENANCE} -- do not edit.\n"
            f"$ EE centre (marker {ee}): position, deviation from the rigid twin (eq. 4.12/4.13),\n"
            "$ vertical acceleration; drive torques of M1-M4; strain gauges of L2r and L3r (GAUGE of\n"
            "$ the l2/l3 artifacts); RZ1, the vertical reaction of the spherical joint at the plate's\n"
            "$ corner (-0.5, -0.5) (JFORCE is defined on coincident-point joints, not on the INLINE and\n"
            "$ INPLANE corners): by the moment balance of the 3-2-1 mount, -g times the first\n"
            "$ moment sum(m x) of the system about the plate's centre line x = 0.\n")
    path.write_text(head + "".join(card("MSENSOR", k, *r) for k, r in enumerate(rows, start=1)))


def main() -> None:
    rigid = rigid_bodies()
    links = {}
    for _, name, _, mesh, pl, (rho, t) in LINKS:
        links[name] = shell_properties(MESHES / f"{mesh}.bdf", rho, t, pl.to_global)
    info = write_include(OUT / "robot_bodies.inc", True, rigid, links)
    write_include(OUT / "robot_rigid_bodies.inc", False, rigid, links)
    write_sensors(OUT / "robot_sensors.inc", info)
    ref = REPO / "reference" / "robot"
    ref.mkdir(parents=True, exist_ok=True)
    doc = {"provenance": PROVENANCE, "units": "SI; global axes, arm upright",
           "bodies": {k: v.as_json() for k, v in (links | rigid).items()},
           "table_4_4": MASS, "gravity": [0.0, 0.0, -9.81], **info,
           "ee_centre": EE_CENTRE.tolist()}
    (ref / "mass_properties.json").write_text(json.dumps(doc, indent=1) + "\n")
    for k, v in (links | rigid).items():
        print(f"{k:5s} m = {v.mass:8.4f} kg  cg = {np.round(v.cg, 4)}")


if __name__ == "__main__":
    main()
