"""Measurements for the AMANDA-EKF Robolink cases (thesis §9.4.2, Table 9.2).

The truth is a forward SOL FMB run of decks/robot/fmb/robot_trajectory{1,2}.dat whose flexible
bodies (plate, L1, L2, L3) are NON-parametric ROMs reduced at the true parameters with 40
normal modes each (each pROM deck with its PMPAR boxes shrunk to the point, one sample, NMODES
40: 52 DOFs per link and 55 for the plate instead of the filter's 22 and 25, the second
reference of docs/robot.md), so the data come neither from the filter's pROMs nor from a basis
of their size. The run starts, as the filter, from the kinematic assembly at t = 0 (the robot
released under gravity in its reference configuration; SOL ESTIMATE starts there) and
integrates with BDF1 at Δt = 1 ms. The gauges read from the reference configuration (thesis
eq. 9.24, "relative" strains): each column is the strain minus its value in the static
equilibrium at t = 0 of the same truth model (a second run with FMBSTART = STATIC), plus
zero-mean white Gaussian noise of standard deviation 1e-7 (§9.4.2.1), seeded per case.

Gauges: EPS2 and EPS3 (Chapter 4's gauges on L2r and L3r, SENSOR GAUGE of l2_prom.dat and
l3_prom.dat) and EPS2B, EPS3B (their GAUGEB: the opposite edge of the same section, the extra
gauge per link of Fig. 9.10).

Cases (``--case``):

- ``e``: E of L2r and L3r constant at their true values (201.99 and 194.37 GPa, Table 4.6);
  columns EPS2, EPS3.
- ``degrading``: L2r's E falls by 10 % of its initial value in 6 s, E_2r(t) = E (1 − t / 60)
  (§9.4.2.1), from a PTABLE on L2R.E (the L2 ROM keeps its E box: one material, so K is exactly
  affine in E; L2l keeps the true E by PVAL); columns EPS2, EPS3 and the truth L2R.E(t).
- ``input``: a 10 Hz sine of 10 N along global x at the tip of the end effector (marker 2003,
  the top of the EE box, 50 mm above its centre) from t = 3 s (Fig. 9.9; the thesis gives
  neither amplitude nor direction in its text: 10 N as the four-bar's, horizontal so that the
  side links bend in their plane); columns EPS2, EPS2B, EPS3, EPS3B and the force.

Writes reference/amanda_robot_<case>_traj<n>.csv (time, the noisy relative gauges, the truth
columns), 9 significant digits (the noise is 1e-7, the strains below 1e-4).

    .venv/bin/python tools/amanda/robot_measurements.py --trajectory 1 --case e
        [--steps 9000] [--binary PATH]
"""

import argparse
import pathlib
import re
import shutil
import sys
import tempfile

import h5py
import numpy as np

from paraflex_tools.prom_decks import absolute_includes, rom_deck_e_rho
from paraflex_tools.runner import default_binary, run_checked

ROOT = pathlib.Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT / "tools" / "robot"))
from static_map import BODIES, with_modes  # noqa: E402

DECKS = ROOT / "decks/robot/fmb"
NOISE = 1e-7
TRUTH_MODES = 40
SEEDS = {("e", 1): 20261201, ("e", 2): 20261202, ("degrading", 1): 20261203,
         ("degrading", 2): 20261204, ("input", 1): 20261205, ("input", 2): 20261206}
EXTRA_GAUGES = "MSENSOR,21,EPS2B,STRAIN,3,GAUGEB\nMSENSOR,22,EPS3B,STRAIN,5,GAUGEB\n"
E2, E3 = BODIES["l2"][0], BODIES["l3"][0]
DEGRADING_TIME = 60.0  # s: 10 % of E in 6 s
INPUT_HZ, INPUT_N, INPUT_START = 10.0, 10.0, 3.0
EE_TIP_Z = 1.233426015568955 + 0.05
INPUT_CARDS = (f"MARKER,2003,20,,0.0,0.0,{EE_TIP_Z!r}\n"
               "MFORCE,7,2003,8,1.,1.,0.,0.\nTABLEF,8,'input.csv',time,force\n")


def l2_modulus(t: np.ndarray) -> np.ndarray:
    """The degrading case's E_2r(t) = E (1 − t / 60 s): −10 % in 6 s."""
    return E2 * (1.0 - t / DEGRADING_TIME)


def input_force(t: np.ndarray) -> np.ndarray:
    """The input F(t) = 10 sin(2π 10 (t − 3)) N from t = 3 s, zero before."""
    return np.where(t >= INPUT_START, INPUT_N * np.sin(2.0 * np.pi * INPUT_HZ * (t - INPUT_START)), 0.0)


def truth_artifact(name: str, keep_e: bool) -> str:
    """The truth ROM deck of body `name` (module docs); with `keep_e` E keeps its box."""
    text = absolute_includes((DECKS / f"{name}_prom.dat").read_text(), DECKS)
    e, rho = BODIES[name]
    rom = with_modes(rom_deck_e_rho(text, 1, e, rho), TRUTH_MODES)
    if keep_e:
        box = re.search(r"^PMPAR,\d+,E,E,1,[^\n]+$", text, flags=re.M).group(0)
        rom = re.sub(r"^PMPAR,\d+,E,E,1,[^\n]+$", box, rom, flags=re.M)
    return rom


def forward_deck(trajectory: int, case: str, steps: int) -> str:
    """The truth's SOL FMB deck (module docs), started from the assembly."""
    text = (DECKS / f"robot_trajectory{trajectory}.dat").read_text()
    text = text.replace("TSTEP,1,9000,1.e-3,1", f"TSTEP,1,{steps},1.e-3,1")
    text = text.replace("FMBSTART = STATIC\n", "")
    cards = EXTRA_GAUGES
    if case == "degrading":
        t1 = steps * 1e-3
        text = text.replace("LOAD = 1\n", "LOAD = 1\nPVAL = 1\n")
        cards += (f"PVAL,1,L2L.E,{E2!r}\nPTABLE,1,L2R.E,9\n"
                  f"TABLED1,9\n,0.,{E2!r},{t1!r},{float(l2_modulus(np.array(t1)))!r},ENDT\n")
    if case == "input":
        cards += INPUT_CARDS
    return text.replace("ENDDATA", cards + "ENDDATA")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--trajectory", type=int, choices=(1, 2), required=True)
    parser.add_argument("--case", choices=("e", "degrading", "input"), required=True)
    parser.add_argument("--steps", type=int, default=9000)
    parser.add_argument("--binary", default=None)
    args = parser.parse_args()
    gauges = ["EPS2", "EPS2B", "EPS3", "EPS3B"] if args.case == "input" else ["EPS2", "EPS3"]
    binary = args.binary or default_binary()
    with tempfile.TemporaryDirectory() as tmp:
        d = pathlib.Path(tmp)
        for name in BODIES:
            path = d / f"{name}_prom.dat"
            path.write_text(truth_artifact(name, args.case == "degrading" and name == "l2"))
            run_checked(path, d / f"{name}.h5", binary)
        for f in ("robot_bodies.inc", "robot_sensors.inc", f"trajectory{args.trajectory}.inc",
                  f"trajectory{args.trajectory}.csv"):
            shutil.copy(DECKS / f, d / f)
        grid = np.arange(4 * args.steps + 1) * 0.25e-3
        np.savetxt(d / "input.csv", np.column_stack([grid, input_force(grid)]), delimiter=",",
                   header="time,force", comments="", fmt="%.17g")
        fmb = forward_deck(args.trajectory, args.case, args.steps)
        (d / "forward.dat").write_text(fmb)
        run_checked(d / "forward.dat", d / "forward.h5", binary)
        with h5py.File(d / "forward.h5", "r") as f:
            g = f["results/1/fmb"]
            time = g["time"][()]
            clean = np.column_stack([g[f"sensors/{n}"][()] for n in gauges])
        static = fmb.replace(f"TSTEP,1,{args.steps},1.e-3,1", "TSTEP,1,1,1.e-3,1")
        static = static.replace("TSTEP = 1\n", "TSTEP = 1\nFMBSTART = STATIC\n", 1)
        (d / "static.dat").write_text(static)
        run_checked(d / "static.dat", d / "static.h5", binary)
        with h5py.File(d / "static.h5", "r") as f:
            reference = np.array([f[f"results/1/fmb/sensors/{n}"][0] for n in gauges])
    seed = SEEDS[(args.case, args.trajectory)]
    noisy = clean - reference + NOISE * np.random.default_rng(seed).standard_normal(clean.shape)
    columns, names = [time, noisy], ["time"] + gauges
    what = "E of L2r and L3r constant"
    if args.case == "degrading":
        columns.append(l2_modulus(time))
        names.append("L2R.E")
        what = f"E of L2r degrading as E (1 - t / {DEGRADING_TIME:g} s) by PTABLE (the L2 ROM parametric in E)"
    if args.case == "input":
        columns.append(input_force(time))
        names.append("force")
        what = (f"the input MFORCE 7 = {INPUT_N:g} sin(2 pi {INPUT_HZ:g} (t - {INPUT_START:g})) N from "
                f"t = {INPUT_START:g} s at the EE tip (marker 2003) along x")
    header = (
        f"AMANDA-EKF Robolink measurements (thesis 9.4.2), trajectory #{args.trajectory}, {what}: "
        f"SOL FMB of decks/robot/fmb/robot_trajectory{args.trajectory}.dat from the assembly, "
        f"its flexible bodies non-parametric ROMs with {TRUTH_MODES} modes at the true E, RHO "
        "(tools/amanda/robot_measurements.py), dt = 1 ms, strains relative to the truth's static "
        "equilibrium at t = 0 (" + ", ".join(f"{n} {r:.10g}" for n, r in zip(gauges, reference))
        + f") with white Gaussian noise sigma = {NOISE:g} (seed {seed})\n" + ",".join(names)
    )
    out = ROOT / "reference" / f"amanda_robot_{args.case}_traj{args.trajectory}.csv"
    np.savetxt(out, np.column_stack(columns), delimiter=",", header=header, fmt="%.9g")
    print(f"wrote {out} ({len(time)} rows)")


if __name__ == "__main__":
    main()
