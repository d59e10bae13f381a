"""The composite link libraries of the Robolink (thesis §6.3.1) and the composite robot.

Writes, in ``decks/robot/fmb/composite/``:

* ``l2_<n>ply_prom.dat`` and ``l3_<n>ply_prom.dat`` for n = 6, 8, 10, 12 plies of 0.3 mm: the
  ``SOL PROM`` decks of one composite side of L2 and of L3 (meshes/robot.py's simplified sides,
  Fig. 6.3), an angle-ply laminate [+Θ/−Θ/…]s with the fibre angle Θ ∈ [0°, 90°] as the pROM's
  parameter (``PMPAR THETA``); the ply count is not affine, so each count is its own artifact and
  a ``PROMLIB`` chooses among them (§6.3.1: "a library of models, differing from each other only
  for the number of layers");
* ``robot_composite_bodies.inc``: the mechanism of ``../robot_bodies.inc`` (tools/robot/model.py)
  with the four composite sides' 8-ply artifacts in place of the steel ones, and
  ``robot_composite_l2_bodies.inc`` with only the L2 sides composite;
* ``robot_composite_trajectory1.dat``: trajectory #1 of the composite robot at Θ₂ = Θ₃ = 45°;
* ``optimize_case1.dat`` and ``optimize_case2.dat``: the design studies of thesis §6.4 on
  trajectory #1 — case 1 (Θ₂, n_l2: both L2 sides composite) and case 2 (Θ₂, n_l2, Θ₃, n_l3),
  the two objectives of eq. 6.1 (the mean EE deviation from the rigid twin and the actuation
  energy of every drive), 105 designs of NSGA-II, no constraint (§6.3.2).

Settings (thesis Table 3.4 for the composite L2r pROM: 10 samples, 16 modes per sample, 0–500 Hz,
FRF tolerance 1e-3; attachment modes at both motor axes as the steel links' decks; Table 3.6:
the ply, Rayleigh α = 5 1/s, β = 3e-6 s). Each side's two strain gauges (``GAUGE``, ``GAUGEB``)
sit on the composite mesh's shell nearest to the steel side's gauge of the same name, so that the
robot's ``STRAIN`` sensors read every artifact of a library.

Masses (Tables 6.1–6.2, sum of both sides): ρ t A of the meshed outline, printed; the outline of
meshes/robot.py was sized for 8 plies, so the other counts scale with the thickness.

Run: ``.venv/bin/python tools/robot/composite_library.py`` (writes the decks; about 1 s). Build the
artifacts with ``paraflex run <deck> -o <artifact>`` in that directory (each about 20–60 s).
"""
from __future__ import annotations

import argparse
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import model  # noqa: E402  (tools/robot/model.py: the mechanism writer)

from paraflex_tools.cards import card  # noqa: E402

PROVENANCE = "tools/robot/composite_library.py"
OUT = model.OUT / "composite"
PLIES = (6, 8, 10, 12)
PLY_T = 0.3e-3
THETA = 45.0                     # the trajectory deck's fibre angle
RHO_C = 1560.0                   # ply density (rule of mixtures, Table 3.6)
# Table 6.1 / 6.2: composite mass of both sides [kg] per ply count
TABLE_MASS = {"l2": {6: 0.2652, 8: 0.3536, 10: 0.4420, 12: 0.5304},
              "l3": {6: 0.1680, 8: 0.2240, 10: 0.2800, 12: 0.3360}}
# the steel sides' gauges (decks/robot/fmb/l2_prom.dat, l3_prom.dat): element ids in l2/l3.bdf
STEEL_GAUGES = {"l2": {"GAUGE": 436, "GAUGEB": 441}, "l3": {"GAUGE": 408, "GAUGEB": 383}}
BODIES = {"l2": ("L2R", "L2L"), "l3": ("L3R", "L3L")}


def shells(path: Path) -> dict[int, np.ndarray]:
    """Element id → centroid of every CQUAD4/CTRIA3 of a meshes/robot include."""
    grids, _ = model.read_shell_mesh(path)
    out = {}
    for line in path.read_text().splitlines():
        if line.startswith(("CQUAD4", "CTRIA3")):
            n = 4 if line.startswith("CQUAD4") else 3
            nodes = [int(line[k:k + 8]) for k in range(24, 24 + 8 * n, 8)]
            out[int(line[8:16])] = np.mean([grids[g] for g in nodes], axis=0)
    return out


def area(path: Path) -> float:
    grids, elements = model.read_shell_mesh(path)
    total = 0.0
    for nodes in elements:
        x = [grids[g] for g in nodes]
        for a, b in ((1, 2), (2, 3))[: len(x) - 2]:
            total += 0.5 * np.linalg.norm(np.cross(x[a] - x[0], x[b] - x[0]))
    return total


def gauges(link: str) -> dict[str, int]:
    """The composite side's shells nearest to the steel side's gauges."""
    steel = shells(model.MESHES / f"{link}.bdf")
    composite = shells(model.MESHES / f"{link}_composite.bdf")
    ids = np.array(list(composite))
    xyz = np.array(list(composite.values()))
    out = {}
    for name, eid in STEEL_GAUGES[link].items():
        d = np.linalg.norm(xyz - steel[eid], axis=1)
        out[name] = int(ids[np.argmin(d)])
        print(f"{link} {name}: steel CQUAD4 {eid} at {np.round(steel[eid], 4)} -> composite "
              f"{out[name]} at {np.round(composite[out[name]], 4)} ({d.min() * 1e3:.1f} mm apart)")
    return out


def laminate(plies: int) -> str:
    """PCOMP 1 of ``plies`` plies of MAT8 2, [+Θ/−Θ/…]s listed to the mid-plane (SYM)."""
    fields: list = [None] * 6 + ["SYM"]
    for k in range(plies // 2):
        fields += [2, PLY_T, 20.0 if k % 2 == 0 else -20.0, None]
    return card("PCOMP", 1, *fields)


def prom_deck(link: str, plies: int, gauge: dict[str, int]) -> str:
    mass = RHO_C * plies * PLY_T * area(model.MESHES / f"{link}_composite.bdf")
    side = {"l2": "second", "l3": "third"}[link]
    head = f"""$ generated by {PROVENANCE} -- do not edit.
$ Robolink (thesis sec. 6.3.1): pROM of one composite side of the {side} link, {plies} plies of
$ 0.3 mm, angle-ply [+T/-T/...]s, the fibre angle THETA over [0, 90] deg as the parameter (the
$ ply angles below are the nominal 20 deg of Table 3.6; PMPAR THETA sets every ply to +-THETA).
$ Mesh: meshes/robot.py (the simplified side of Fig. 6.3), masters 1000001/1000002 on the motor
$ axes (ASET1: 12 attachment modes), RIGID = REMOVE (a floating-frame body of the robot).
$ Settings of thesis Table 3.4: 10 LHS samples, 16 modes per sample, 0-500 Hz, FRF tolerance
$ 1e-3. Ply from Table 3.6 by micromechanics (decks/robot/l2r_composite_free.dat), Rayleigh
$ alpha = 5 1/s, beta = 3e-6 s (Table 3.6).
$ Mass of the side: {mass:.4f} kg (Table 6.{1 if link == 'l2' else 2}: {TABLE_MASS[link][plies] / 2:.4f} kg per side).
$ Gauges: GAUGE and GAUGEB on the shells nearest to the steel side's (decks/robot/fmb/{link}_prom.dat).
$ Run: paraflex run {link}_{plies}ply_prom.dat -o {link}_{plies}ply.h5
"""
    body = [
        "SOL PROM\nCEND\n",
        f"TITLE = Robolink {link.upper()} composite side, {plies} plies, THETA over [0, 90] deg\n",
        "PROM = 1\nBEGIN BULK\n",
        f"INCLUDE '../../../../meshes/robot/{link}_composite.bdf'\n",
        f"INCLUDE '../../../../meshes/robot/{link}_composite_rbe.bdf'\n",
        "MAT8,2,145.2E9,7.362E9,0.336,2.767E9,,,1560.\n",
        laminate(plies),
        "PMPAR,1,THETA,THETA,1,0.,90.\n",
        card("SENSOR", 1, "GAUGE", "STRAIN", gauge["GAUGE"], "TOP", 1.0, 0.0, 0.0),
        card("SENSOR", 2, "GAUGEB", "STRAIN", gauge["GAUGEB"], "TOP", 1.0, 0.0, 0.0),
        "PARAM,ALPHA1,5.\nPARAM,BETA1,3.E-6\n",
        "PMOR,1,10,16,500.,1.E-3,5\n,1,ATTACH,REMOVE,40\n",
        "ENDDATA\n",
    ]
    return head + "".join(body)


def run_deck(sol: str, title: str, pval: str, bodies: str, bulk: str = "") -> str:
    """The case control and bulk data shared by the trajectory and study decks: trajectory #1
    (9 s, BDF1 at 1 ms, from the static equilibrium) of the mechanism include ``bodies``."""
    return f"""SOL {sol}
CEND
TITLE = {title}
TSTEP = 1
LOAD = 1
PVAL = 1
FMBSTART = STATIC
BEGIN BULK
TSTEP,1,9000,1.e-3,1
TINTEG,1,BDF1
{pval}INCLUDE '{bodies}'
INCLUDE '../robot_sensors.inc'
INCLUDE '../trajectory1.inc'
{bulk}ENDDATA
"""


def trajectory_deck() -> str:
    pval = card("PVAL", 1, *(f for pair in BODIES.values() for b in pair for f in (f"{b}.THETA", THETA)))
    return f"""$ generated by {PROVENANCE} -- do not edit.
$ Robolink pFMB with composite L2 and L3 sides (thesis sec. 4.5.5, 6.3): trajectory #1 at
$ THETA = {THETA:g} deg on every side, 8 plies (robot_composite_bodies.inc). Build the artifacts
$ first (see l2_8ply_prom.dat, l3_8ply_prom.dat) and the plate and L1 artifacts one directory up.
""" + run_deck("FMB", f"Robolink pFMB, composite L2/L3 at THETA = {THETA:g} deg, trajectory #1", pval,
               "robot_composite_bodies.inc")


def study_deck(case: int, links: tuple[str, ...], bodies: str) -> str:
    """The design study of thesis §6.4 case ``case``: fibre angle and ply count of ``links``."""
    variables, cards_ = [], []
    for k, link in enumerate(links):
        n = link[1]
        theta, plies = 2 * k + 1, 2 * k + 2
        right, left = BODIES[link]
        variables.append(f"THETA{n}, NL{n}")
        cards_ += [
            card("DESVAR", theta, f"THETA{n}", 20.0, 0.0, 90.0),
            card("DESVAR", plies, f"NL{n}", 8.0, None, None, None, plies),
            card("DDVAL", plies, *[float(p) for p in PLIES]),
            card("DVMAP", theta, theta, f"{right}.THETA", f"{left}.THETA"),
            card("DVMAP", plies, plies, right, left),
        ]
        for bid, body in enumerate((right, left)):
            library = [f for p in PLIES for f in (float(p), f"'{link}_{p}ply.h5'")]
            cards_.append(card("PROMLIB", 10 * (k + 1) + bid, body, *library))
    pval = card("PVAL", 1, *(f for link in links for b in BODIES[link] for f in (f"{b}.THETA", 20.0)))
    thesis = {1: "Table 6.5: 8 h", 2: "Table 6.7: 16 h 53 min"}[case]
    return f"""$ generated by {PROVENANCE} -- do not edit.
$ Robolink design study, thesis sec. 6.4 case {case}: {', '.join(variables)} (fibre angle over
$ [0, 90] deg, plies 6/8/10/12 from each side's PROMLIB), the {'L2' if case == 1 else 'L2 and L3'}
$ sides composite, on trajectory #1 (9 s, BDF1 at 1 ms). Objectives of eq. 6.1: f1 the mean
$ deviation of the EE from the rigid twin (EEDEV, MEAN), f2 the actuation energy of every drive
$ (ETOT: ENERGY with REF blank, FINAL); no constraint (sec. 6.3.2). 105 designs as the thesis
$ ({thesis} with HEEDS SHERPA and Matlab): NSGA-II, population 15, 2 evaluations at a time.
$ Build the library artifacts beside this deck ({', '.join(f'{l}_<n>ply_prom.dat' for l in links)}) and
$ plate.h5, l1.h5{', l3.h5' if case == 1 else ''} one directory up; then
$ paraflex run optimize_case{case}.dat -o case{case}.h5 (tools/optimize/plot_study.py draws it).
""" + run_deck("OPTIMIZE", f"Robolink design study, thesis case {case}", pval, bodies,
               "MSENSOR,20,ETOT,ENERGY\n" + "".join(cards_)
               + "DOBJ,1,DEV,MIN,EEDEV,MEAN\nDOBJ,2,ENERGY,MIN,ETOT,FINAL\nMOOPT,1,NSGA2,105,15,1,2\n")


def files() -> dict[Path, str]:
    """Every file this generator writes, with its text."""
    out = {}
    for link in BODIES:
        gauge = gauges(link)
        a = area(model.MESHES / f"{link}_composite.bdf")
        for plies in PLIES:
            out[OUT / f"{link}_{plies}ply_prom.dat"] = prom_deck(link, plies, gauge)
            both = 2 * RHO_C * plies * PLY_T * a
            table = TABLE_MASS[link][plies]
            print(f"{link} {plies:2d} plies: both sides {both:.4f} kg, table {table:.4f} kg "
                  f"({100 * (both / table - 1):+.1f} %)")
    artifacts = {b: f"{link}_8ply.h5" for link, pair in BODIES.items() for b in pair}
    # the other bodies' artifacts are one directory up, beside robot_bodies.inc
    artifacts |= {name: f"../{artifact}" for _, name, artifact, *_ in model.LINKS if name not in artifacts}
    rigid = model.rigid_bodies()
    only_l2 = artifacts | {name: f"../{a}" for _, name, a, *_ in model.LINKS if name in BODIES["l3"]}
    for name, chosen in (("robot_composite_bodies.inc", artifacts), ("robot_composite_l2_bodies.inc", only_l2)):
        out[OUT / name] = model.include_text(name, True, rigid, {}, chosen, PROVENANCE)[0]
    out[OUT / "robot_composite_trajectory1.dat"] = trajectory_deck()
    out[OUT / "optimize_case1.dat"] = study_deck(1, ("l2",), "robot_composite_l2_bodies.inc")
    out[OUT / "optimize_case2.dat"] = study_deck(2, ("l2", "l3"), "robot_composite_bodies.inc")
    return out


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true",
                        help="compare with the committed files instead of writing them")
    args = parser.parse_args()
    stale = []
    for path, text in files().items():
        if args.check:
            if not path.exists() or path.read_text() != text:
                stale.append(path.relative_to(model.REPO))
        else:
            path.parent.mkdir(parents=True, exist_ok=True)
            path.write_text(text)
    if stale:
        print("stale or missing (run tools/robot/composite_library.py):", *stale, sep="\n  ")
        return 1
    print("checked" if args.check else "wrote", OUT.relative_to(model.REPO))
    return 0


if __name__ == "__main__":
    sys.exit(main())
