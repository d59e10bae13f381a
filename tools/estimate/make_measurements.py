#!/usr/bin/env python3
"""Numerical measurements for SOL ESTIMATE (thesis §8.6): sensor series of a paraflex SOL TRANSIENT
on a pROM plus seeded zero-mean Gaussian noise, written as the CSV a MEASF card reads.

Columns: ``time``, one per SENSOR of the transient (noisy), and the true values of the
parameters given with ``--truth NAME=VALUE`` (the transient's PVAL values): SOL ESTIMATE uses
columns named like an estimated parameter for its error table, and columns of sensors it does
not measure as references for their AAE. Noise standard deviations by sensor kind, prefix or
name: ``--sigma ACCEL=1e-3 --sigma STRAIN=1e-7 --sigma D_TIP=2e-7`` (a name beats a kind).

    .venv/bin/python tools/estimate/make_measurements.py transient.h5 -o meas.csv \
        --sigma DISP=1e-7 --sigma ACCEL=1e-3 --truth E=2e11 --truth RHO=7800 --seed 1
"""
from __future__ import annotations

import argparse
import sys

import h5py
import numpy as np

from paraflex_tools.results import text, texts


def parse_pairs(items: list[str], what: str) -> dict[str, str]:
    out = {}
    for item in items:
        if "=" not in item:
            sys.exit(f"{what} '{item}': expected NAME=VALUE")
        name, value = item.split("=", 1)
        out[name.strip().upper()] = value.strip()
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("transient", help="paraflex output of a SOL TRANSIENT on a pROM (with SENSORs)")
    ap.add_argument("-o", "--output", required=True, help="CSV to write")
    ap.add_argument("--subcase", default="1")
    ap.add_argument("--sigma", action="append", default=[], help="KIND|NAME=σ (DISP, VEL, ACCEL, STRAIN or a sensor name)")
    ap.add_argument("--truth", action="append", default=[], help="NAME=VALUE: true parameter values")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--start", type=float, default=0.0, help="drop samples before this time and shift time to start at 0 (non-zero initial conditions, §8.6.4)")
    args = ap.parse_args()

    sigma = {k: float(v) for k, v in parse_pairs(args.sigma, "--sigma").items()}
    truth = parse_pairs(args.truth, "--truth")
    with h5py.File(args.transient, "r") as f:
        g = f[f"results/{args.subcase}/transient"]
        time = g["time"][()]
        names = sorted(g["sensors"].keys())
        series = {n: g["sensors"][n][()] for n in names}
        kinds = {}
        prom = f.get("prom/sensors")
        rom_path = g.attrs.get("rom")
        if prom is None and rom_path is not None:
            with h5py.File(text(rom_path), "r") as r:
                kinds = dict(zip(texts(r["prom/sensors/names"][()]), texts(r["prom/sensors/kind"][()])))
    rng = np.random.default_rng(args.seed)
    keep = time >= args.start - 1e-12
    columns = {"time": time[keep] - args.start}
    for n in names:
        s = sigma.get(n.upper(), sigma.get(kinds.get(n, ""), 0.0))
        columns[n] = series[n][keep] + s * rng.standard_normal(keep.sum())
    for name, value in truth.items():
        columns[name] = np.full(keep.sum(), float(value))
    header = ",".join(columns)
    data = np.column_stack(list(columns.values()))
    np.savetxt(args.output, data, delimiter=",", header=header, comments="", fmt="%.17e")
    print(f"wrote {args.output}: {data.shape[0]} rows, sensors {', '.join(names)} (seed {args.seed})")


if __name__ == "__main__":
    main()
