"""Measurements for the AMANDA-EKF four-bar cases (thesis §9.4.1, Table 9.1, sensor set 1).

The truth is a forward SOL FMB run of decks/fourbar/fmb/fourbar_steel.dat whose three links are
NON-parametric ROMs reduced at the true parameters (each pROM deck with one sample and its PMPAR
boxes shrunk to the point: the same meshes, a different basis from the pROMs the filter runs),
so the data do not come from the model the filter predicts with. The gauges are the mid-span
MIDX gauge of each link (ICEPS, CEPS, OCEPS: one per component, set 1), plus zero-mean white
Gaussian noise of standard deviation 1e-7 (§9.4.1.1), seeded.

Writes reference/amanda_fourbar_set1.csv: time and the three noisy strains per step (t = 0
included), and the noise-free ones, with a header naming the provenance.

With --input (Table 9.1's "E_C, input" case) the forward run also applies the 15 Hz, 10 N sine
F(t) = 10 sin(2π 15 t) N as an MFORCE (id 7) at marker 32, OC's end at the coupler joint,
along global x (perpendicular to OC in the initial configuration): the thesis loads OC's
centre of mass out of plane, but the OC artifact's interface grids are its two joint masters
only, so the load sits at the one that is not grounded, in the mechanism's plane where the
mid-span gauges read bending. The table is sampled every 0.25 ms (its linear interpolation is
exact at the 1 ms steps). Writes reference/amanda_fourbar_input_set1.csv with the same columns
plus the applied force (column "force"); the noise has its own seed.

With --relative the gauges read from the reference configuration (thesis eq. 9.24): the
static equilibrium at t = 0 (drive at its initial angle, gravity) of the same non-parametric
links, from a second forward run with FMBSTART = STATIC; each column is the absolute strain
minus that reference, with the same noise as the absolute file. Writes
reference/amanda_fourbar_set1_relative.csv (the reference strains in its header).

    .venv/bin/python tools/amanda/fourbar_measurements.py [--steps 1000] [--input | --relative]
        [--binary PATH]
"""

import argparse
import pathlib
import re
import tempfile

import h5py
import numpy as np

from paraflex_tools.runner import default_binary, run_checked

ROOT = pathlib.Path(__file__).resolve().parents[2]
DECKS = ROOT / "decks/fourbar/fmb"
E_TRUE, RHO_TRUE = 201.99e9, 7990.0
NOISE = 1e-7
SEED = 20260924
LINKS = [
    ("crank_prom.dat", "crank.h5"),
    ("coupler_prom.dat", "coupler.h5"),
    ("output_crank_prom.dat", "output_crank.h5"),
]
GAUGES = ["ICEPS", "CEPS", "OCEPS"]
INPUT_SEED = 20261128
INPUT_HZ, INPUT_N = 15.0, 10.0
# the unknown input: MFORCE 7 at marker 32 along x, amplitude from TABLEF 8
INPUT_CARDS = "MFORCE,7,32,8,1.,1.,0.,0.\nTABLEF,8,'input.csv',time,force\n"


def input_force(t: np.ndarray) -> np.ndarray:
    """The input's amplitude F(t) = 10 sin(2π 15 t) N."""
    return INPUT_N * np.sin(2.0 * np.pi * INPUT_HZ * t)


def at_point(text: str) -> str:
    """The pROM deck reduced at (E_TRUE, RHO_TRUE) with one sample: a non-parametric ROM."""
    text = re.sub(r"PMOR,1,\d+,", "PMOR,1,1,", text)
    text = text.replace("PMPAR,1,E,E,1,121.194E9,282.786E9", f"PMPAR,1,E,E,1,{E_TRUE:e},{E_TRUE:e}")
    text = text.replace("PMPAR,2,RHO,RHO,1,4794.,11186.", f"PMPAR,2,RHO,RHO,1,{RHO_TRUE},{RHO_TRUE}")
    return text.replace("'../../../meshes/", f"'{ROOT / 'meshes'}/")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=1000)
    parser.add_argument("--input", action="store_true", help="apply the 15 Hz, 10 N input on OC")
    parser.add_argument("--relative", action="store_true", help="strains from the static reference")
    parser.add_argument("--binary", default=None)
    args = parser.parse_args()
    binary = args.binary or default_binary()
    with tempfile.TemporaryDirectory() as tmp:
        d = pathlib.Path(tmp)
        for deck, artifact in LINKS:
            path = d / deck
            path.write_text(at_point((DECKS / deck).read_text()))
            run_checked(path, d / artifact, binary)
        fmb = (DECKS / "fourbar_steel.dat").read_text()
        fmb = fmb.replace("TSTEP,1,1000,1.e-3,1", f"TSTEP,1,{args.steps},1.e-3,1")
        (d / "drive.csv").write_text((DECKS / "drive.csv").read_text())
        if args.input:
            fmb = fmb.replace("ENDDATA", INPUT_CARDS + "ENDDATA")
            grid = np.arange(4 * args.steps + 1) * 0.25e-3
            np.savetxt(d / "input.csv", np.column_stack([grid, input_force(grid)]), delimiter=",",
                       header="time,force", comments="", fmt="%.17g")
        path = d / "fourbar.dat"
        path.write_text(fmb)
        run_checked(path, d / "fourbar.h5", binary)
        with h5py.File(d / "fourbar.h5", "r") as f:
            g = f["results/1/fmb"]
            time = g["time"][()]
            clean = np.column_stack([g[f"sensors/{n}"][()] for n in GAUGES])
        reference = np.zeros(len(GAUGES))
        if args.relative:
            static = fmb.replace(f"TSTEP,1,{args.steps},1.e-3,1", "TSTEP,1,1,1.e-3,1")
            static = static.replace("TSTEP = 1\n", "TSTEP = 1\nFMBSTART = STATIC\n", 1)
            path = d / "static.dat"
            path.write_text(static)
            run_checked(path, d / "static.h5", binary)
            with h5py.File(d / "static.h5", "r") as f:
                g = f["results/1/fmb"]
                reference = np.array([g[f"sensors/{n}"][0] for n in GAUGES])
    seed = INPUT_SEED if args.input else SEED
    noisy = clean + NOISE * np.random.default_rng(seed).standard_normal(clean.shape)
    noisy, clean = noisy - reference, clean - reference
    name = "amanda_fourbar_input_set1.csv" if args.input else "amanda_fourbar_set1.csv"
    if args.relative:
        name = "amanda_fourbar_set1_relative.csv"
    out = ROOT / "reference" / name
    load = (
        f", with the input MFORCE 7 = {INPUT_N:g} sin(2 pi {INPUT_HZ:g} t) N at marker 32 along x"
        if args.input
        else ""
    )
    header = (
        "AMANDA-EKF four-bar measurements, sensor set 1 (thesis 9.4.1): SOL FMB of "
        "decks/fourbar/fmb/fourbar_steel.dat with its links as non-parametric ROMs at E = "
        f"{E_TRUE:e} Pa, RHO = {RHO_TRUE} kg/m3{load} (tools/amanda/fourbar_measurements.py), "
        f"dt = 1 ms, strains with white Gaussian noise sigma = {NOISE:g} (seed {seed})"
        + (
            ", relative to the static equilibrium at t = 0 (FMBSTART = STATIC), reference strains "
            + ", ".join(f"{n} {r:.17g}" for n, r in zip(GAUGES, reference))
            if args.relative
            else ""
        )
        + "\n"
        "time," + ",".join(GAUGES) + "," + ",".join(f"{n}_clean" for n in GAUGES)
    )
    columns = [time, noisy, clean]
    if args.input:
        header += ",force"
        columns.append(input_force(time))
    np.savetxt(out, np.column_stack(columns), delimiter=",", header=header, fmt="%.17g")
    print(f"wrote {out} ({len(time)} rows)")


if __name__ == "__main__":
    main()
