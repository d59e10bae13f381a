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

With --set2 (sensor set 2 of §9.4.1.1: three gauges on IC only) the gauges are IC's MIDX and
its gauges Q1X and Q3X at a quarter and three quarters of its length (ICEPS, ICQ1EPS,
ICQ3EPS), no input, the links at the true E: reference/amanda_fourbar_set2.csv (own seed).

With --degrading (Table 9.1's "degrading E_C, input" case, §9.4.1.4) the coupler's E falls by
10 % of its initial value per second, E_C(t) = E (1 − 0.1 t), with the input above. The
coupler's ROM keeps its E box (one sample: a single material, so the basis of any E spans
every E and K is exactly affine in it) with RHO shrunk to the point, and the forward run
takes C.E from a PTABLE (its pROM re-evaluated at E_C(t) every step); IC and OC are the
non-parametric ROMs. The file holds the five gauges of both sets (ICEPS, CEPS, OCEPS,
ICQ1EPS, ICQ3EPS; set 1 is the first three, set 2 the IC ones), the force and E_C(t) (column
"CE"): reference/amanda_fourbar_degrading.csv (own seed).

    .venv/bin/python tools/amanda/fourbar_measurements.py [--steps 1000]
        [--input | --relative | --set2 | --degrading] [--binary PATH]
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
# sensor set 2's extra gauges on IC (crank_prom.dat SENSOR Q1X, Q3X)
SET2_CARDS = "MSENSOR,11,ICQ1EPS,STRAIN,1,Q1X\nMSENSOR,12,ICQ3EPS,STRAIN,1,Q3X\n"
SET2 = ["ICEPS", "ICQ1EPS", "ICQ3EPS"]
SET2_SEED = 20261129
DEGRADING_SEED = 20261130
DEGRADING_RATE = 0.1  # of the initial E per second
# C.E from a table in the forward run: linear from E at t = 0 to E (1 - 0.1 t_end)
DEGRADING_CARDS = "PTABLE,1,C.E,9\nTABLED1,9\n,0.,{e0:.15e},{t1:.15e},{e1:.15e},ENDT\n"


def coupler_modulus(t: np.ndarray) -> np.ndarray:
    """The degrading case's E_C(t) = E (1 − 0.1 t)."""
    return E_TRUE * (1.0 - DEGRADING_RATE * t)


def input_force(t: np.ndarray) -> np.ndarray:
    """The input's amplitude F(t) = 10 sin(2π 15 t) N."""
    return INPUT_N * np.sin(2.0 * np.pi * INPUT_HZ * t)


def at_point(text: str, keep_e: bool = False) -> str:
    """The pROM deck reduced at (E_TRUE, RHO_TRUE) with one sample: a non-parametric ROM (with
    `keep_e`, E keeps its box: one sample, parametric in E only)."""
    text = re.sub(r"PMOR,1,\d+,", "PMOR,1,1,", text)
    if not keep_e:
        text = text.replace("PMPAR,1,E,E,1,121.194E9,282.786E9",
                            f"PMPAR,1,E,E,1,{E_TRUE:e},{E_TRUE:e}")
    text = text.replace("PMPAR,2,RHO,RHO,1,4794.,11186.", f"PMPAR,2,RHO,RHO,1,{RHO_TRUE},{RHO_TRUE}")
    return text.replace("'../../../meshes/", f"'{ROOT / 'meshes'}/")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=1000)
    parser.add_argument("--input", action="store_true", help="apply the 15 Hz, 10 N input on OC")
    parser.add_argument("--relative", action="store_true", help="strains from the static reference")
    parser.add_argument("--set2", action="store_true", help="sensor set 2: three gauges on IC")
    parser.add_argument("--degrading", action="store_true",
                        help="E_C degrading 10 %%/s with the input; the gauges of both sets")
    parser.add_argument("--binary", default=None)
    args = parser.parse_args()
    if args.degrading:
        args.input = True
    gauges = SET2 if args.set2 else GAUGES + SET2[1:] if args.degrading else GAUGES
    binary = args.binary or default_binary()
    with tempfile.TemporaryDirectory() as tmp:
        d = pathlib.Path(tmp)
        for deck, artifact in LINKS:
            path = d / deck
            keep_e = args.degrading and artifact == "coupler.h5"
            path.write_text(at_point((DECKS / deck).read_text(), keep_e))
            run_checked(path, d / artifact, binary)
        fmb = (DECKS / "fourbar_steel.dat").read_text()
        fmb = fmb.replace("TSTEP,1,1000,1.e-3,1", f"TSTEP,1,{args.steps},1.e-3,1")
        (d / "drive.csv").write_text((DECKS / "drive.csv").read_text())
        if args.set2 or args.degrading:
            fmb = fmb.replace("ENDDATA", SET2_CARDS + "ENDDATA")
        if args.degrading:
            pval = "PVAL,1,IC.E,201.99E9,IC.RHO,7990.,C.E,201.99E9,C.RHO\n,7990.,OC.E,201.99E9,OC.RHO,7990."
            assert pval in fmb
            fmb = fmb.replace(pval, "PVAL,1,IC.E,201.99E9,IC.RHO,7990.,C.RHO,7990.,OC.E\n"
                              ",201.99E9,OC.RHO,7990.")
            t1 = args.steps * 1e-3
            fmb = fmb.replace("ENDDATA", DEGRADING_CARDS.format(
                e0=E_TRUE, t1=t1, e1=float(coupler_modulus(np.array(t1)))) + "ENDDATA")
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
            clean = np.column_stack([g[f"sensors/{n}"][()] for n in gauges])
        reference = np.zeros(len(gauges))
        if args.relative:
            static = fmb.replace(f"TSTEP,1,{args.steps},1.e-3,1", "TSTEP,1,1,1.e-3,1")
            static = static.replace("TSTEP = 1\n", "TSTEP = 1\nFMBSTART = STATIC\n", 1)
            path = d / "static.dat"
            path.write_text(static)
            run_checked(path, d / "static.h5", binary)
            with h5py.File(d / "static.h5", "r") as f:
                g = f["results/1/fmb"]
                reference = np.array([g[f"sensors/{n}"][0] for n in gauges])
    seed = (DEGRADING_SEED if args.degrading else INPUT_SEED if args.input
            else SET2_SEED if args.set2 else SEED)
    noisy = clean + NOISE * np.random.default_rng(seed).standard_normal(clean.shape)
    noisy, clean = noisy - reference, clean - reference
    name = "amanda_fourbar_input_set1.csv" if args.input else "amanda_fourbar_set1.csv"
    if args.relative:
        name = "amanda_fourbar_set1_relative.csv"
    if args.set2:
        name = "amanda_fourbar_set2.csv"
    if args.degrading:
        name = "amanda_fourbar_degrading.csv"
    out = ROOT / "reference" / name
    load = (
        f", with the input MFORCE 7 = {INPUT_N:g} sin(2 pi {INPUT_HZ:g} t) N at marker 32 along x"
        if args.input
        else ""
    )
    sets = "sensor set 2" if args.set2 else "sensor sets 1 and 2" if args.degrading else "sensor set 1"
    if args.degrading:
        load += (
            f"; the coupler's E degrading as E (1 - {DEGRADING_RATE:g} t) (PTABLE on C.E, its ROM "
            "parametric in E, one sample)"
        )
    header = (
        f"AMANDA-EKF four-bar measurements, {sets} (thesis 9.4.1): SOL FMB of "
        "decks/fourbar/fmb/fourbar_steel.dat with its links as non-parametric ROMs at E = "
        f"{E_TRUE:e} Pa, RHO = {RHO_TRUE} kg/m3{load} (tools/amanda/fourbar_measurements.py), "
        f"dt = 1 ms, strains with white Gaussian noise sigma = {NOISE:g} (seed {seed})"
        + (
            ", relative to the static equilibrium at t = 0 (FMBSTART = STATIC), reference strains "
            + ", ".join(f"{n} {r:.17g}" for n, r in zip(gauges, reference))
            if args.relative
            else ""
        )
        + "\n"
        "time," + ",".join(gauges) + "," + ",".join(f"{n}_clean" for n in gauges)
    )
    columns = [time, noisy, clean]
    if args.input:
        header += ",force"
        columns.append(input_force(time))
    if args.degrading:
        header += ",CE"
        columns.append(coupler_modulus(time))
    np.savetxt(out, np.column_stack(columns), delimiter=",", header=header, fmt="%.17g")
    print(f"wrote {out} ({len(time)} rows)")


if __name__ == "__main__":
    main()
