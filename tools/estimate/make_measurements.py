#!/usr/bin/env python3
"""Numerical measurements for SOL ESTIMATE (thesis §8.6): sensor series plus seeded zero-mean
Gaussian noise, written as the CSV a MEASF card reads. The series come from a paraflex SOL
TRANSIENT on a pROM (first form below), or, independently of paraflex's integrators, from the
exact response of a pROM artifact at the true parameters to a load table (``--simulate``:
``paraflex_tools.prom.Prom.response``, first-order hold between the table's samples).

Columns: ``time``, one per SENSOR of the transient (noisy), and the true values of the
parameters given with ``--truth NAME=VALUE`` (the transient's PVAL values): SOL ESTIMATE uses
columns named like an estimated parameter for its error table, and columns of sensors it does
not measure as references for their AAE. Noise standard deviations by sensor kind, prefix or
name: ``--sigma ACCEL=1e-3 --sigma STRAIN=1e-7 --sigma D_TIP=2e-7`` (a name beats a kind).

    .venv/bin/python tools/estimate/make_measurements.py transient.h5 -o meas.csv \
        --sigma DISP=1e-7 --sigma ACCEL=1e-3 --truth E=2e11 --truth RHO=7800 --seed 1
    .venv/bin/python tools/estimate/make_measurements.py --simulate prom.h5 --load load.csv \
        --dt 1e-4 --steps 5000 -o meas.csv --sigma DISP=1e-7 --truth E=2e11 --truth RHO=7800

With ``--simulate`` the ``--truth`` values are also the point the pROM is evaluated at (the
others keep their nominal values) and the load table (columns time, force: the force on the
pROM's one input, linear between rows, as TABLEF) must cover [0, steps·dt].
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


def from_transient(path: str, subcase: str):
    """Times, sensor series and sensor kinds of a paraflex SOL TRANSIENT on a pROM."""
    with h5py.File(path, "r") as f:
        g = f[f"results/{subcase}/transient"]
        time = g["time"][()]
        series = {n: g["sensors"][n][()] for n in g["sensors"].keys()}
        kinds = {}
        rom_path = g.attrs.get("rom")
        if f.get("prom/sensors") is None and rom_path is not None:
            with h5py.File(text(rom_path), "r") as r:
                kinds = dict(zip(texts(r["prom/sensors/names"][()]), texts(r["prom/sensors/kind"][()])))
    return time, series, kinds


def simulated(args, truth: dict[str, str]):
    """Times, sensor series and sensor kinds of the exact response of the pROM ``--simulate`` at
    the ``--truth`` point to the ``--load`` table."""
    from paraflex_tools.prom import Prom

    if args.load is None or args.dt is None or args.steps is None:
        sys.exit("--simulate needs --load, --dt and --steps")
    model = Prom(args.simulate)
    if model.input_shapes.shape[1] != 1:
        sys.exit(f"--simulate: the pROM has {model.input_shapes.shape[1]} inputs; the load table drives one")
    table = np.loadtxt(args.load, delimiter=",", skiprows=1, ndmin=2)
    time = np.arange(args.steps + 1) * args.dt
    if table[0, 0] > 0.0 or table[-1, 0] < time[-1] * (1 - 1e-12):
        sys.exit(f"--load covers [{table[0, 0]}, {table[-1, 0]}], not [0, {time[-1]}]")
    force = np.interp(time, table[:, 0], table[:, 1])
    point = {name: float(value) for name, value in truth.items() if name in model.parameter_names}
    response = model.response(time, force[:, None], point)
    series = {name: response[:, k] for k, name in enumerate(model.sensor_names)}
    return time, series, dict(zip(model.sensor_names, model.sensor_kinds))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("transient", nargs="?", help="paraflex output of a SOL TRANSIENT on a pROM (with SENSORs)")
    ap.add_argument("--simulate", metavar="PROM", help="a pROM artifact: simulate it exactly instead of reading a transient")
    ap.add_argument("--load", help="with --simulate: CSV table time,force of the load on the pROM's input")
    ap.add_argument("--dt", type=float, help="with --simulate: sample interval")
    ap.add_argument("--steps", type=int, help="with --simulate: number of intervals")
    ap.add_argument("-o", "--output", required=True, help="CSV to write")
    ap.add_argument("--subcase", default="1")
    ap.add_argument("--sigma", action="append", default=[], help="KIND|NAME=σ (DISP, VEL, ACCEL, STRAIN or a sensor name)")
    ap.add_argument("--truth", action="append", default=[], help="NAME=VALUE: true parameter values")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--start", type=float, default=0.0, help="drop samples before this time and shift time to start at 0 (non-zero initial conditions, §8.6.4)")
    args = ap.parse_args()

    sigma = {k: float(v) for k, v in parse_pairs(args.sigma, "--sigma").items()}
    truth = parse_pairs(args.truth, "--truth")
    if args.simulate:
        time, series, kinds = simulated(args, truth)
    elif args.transient:
        time, series, kinds = from_transient(args.transient, args.subcase)
    else:
        sys.exit("give a transient output file or --simulate PROM")
    names = sorted(series)
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
