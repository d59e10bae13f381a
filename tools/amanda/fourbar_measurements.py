"""Measurements for the AMANDA-EKF four-bar case (thesis §9.4.1, Table 9.1, sensor set 1).

The truth is a forward SOL FMB run of decks/fourbar/fmb/fourbar_steel.dat whose three links are
NON-parametric ROMs reduced at the true parameters (each pROM deck with one sample and its PMPAR
boxes shrunk to the point: the same meshes, a different basis from the pROMs the filter runs),
so the data do not come from the model the filter predicts with. The gauges are the mid-span
MIDX gauge of each link (ICEPS, CEPS, OCEPS: one per component, set 1), plus zero-mean white
Gaussian noise of standard deviation 1e-7 (§9.4.1.1), seeded.

Writes reference/amanda_fourbar_set1.csv: time and the three noisy strains per step (t = 0
included), and the noise-free ones, with a header naming the provenance.

    .venv/bin/python tools/amanda/fourbar_measurements.py [--steps 1000] [--binary PATH]
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


def at_point(text: str) -> str:
    """The pROM deck reduced at (E_TRUE, RHO_TRUE) with one sample: a non-parametric ROM."""
    text = re.sub(r"PMOR,1,\d+,", "PMOR,1,1,", text)
    text = text.replace("PMPAR,1,E,E,1,121.194E9,282.786E9", f"PMPAR,1,E,E,1,{E_TRUE:e},{E_TRUE:e}")
    text = text.replace("PMPAR,2,RHO,RHO,1,4794.,11186.", f"PMPAR,2,RHO,RHO,1,{RHO_TRUE},{RHO_TRUE}")
    return text.replace("'../../../meshes/", f"'{ROOT / 'meshes'}/")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=1000)
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
        path = d / "fourbar.dat"
        path.write_text(fmb)
        run_checked(path, d / "fourbar.h5", binary)
        with h5py.File(d / "fourbar.h5", "r") as f:
            g = f["results/1/fmb"]
            time = g["time"][()]
            clean = np.column_stack([g[f"sensors/{n}"][()] for n in GAUGES])
    noisy = clean + NOISE * np.random.default_rng(SEED).standard_normal(clean.shape)
    out = ROOT / "reference/amanda_fourbar_set1.csv"
    header = (
        "AMANDA-EKF four-bar measurements, sensor set 1 (thesis 9.4.1): SOL FMB of "
        "decks/fourbar/fmb/fourbar_steel.dat with its links as non-parametric ROMs at E = "
        f"{E_TRUE:e} Pa, RHO = {RHO_TRUE} kg/m3 (tools/amanda/fourbar_measurements.py), "
        f"dt = 1 ms, strains with white Gaussian noise sigma = {NOISE:g} (seed {SEED})\n"
        "time," + ",".join(GAUGES) + "," + ",".join(f"{n}_clean" for n in GAUGES)
    )
    np.savetxt(out, np.column_stack([time, noisy, clean]), delimiter=",", header=header, fmt="%.17g")
    print(f"wrote {out} ({len(time)} rows)")


if __name__ == "__main__":
    main()
