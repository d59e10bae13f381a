#!/usr/bin/env python3
"""Plots of a SOL ESTIMATE result (analogues of thesis Fig. 8.8–8.13): each estimated parameter
and input against time with its ±3σ band and the true value when the measurement CSV has it,
a zoom window on the last part, and the AAE / MRA of every sensor (measured and virtual).

    .venv/bin/python tools/estimate/plot_estimate.py est.h5 --measurements meas.csv \
        --zoom 0.8 1.0 -o estimate.png
"""
from __future__ import annotations

import argparse

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("result", help="paraflex output of SOL ESTIMATE")
    ap.add_argument("--subcase", default="1")
    ap.add_argument("--measurements", help="the MEASF CSV (true values in columns named like the unknowns)")
    ap.add_argument("--zoom", nargs=2, type=float, metavar=("T0", "T1"), help="zoom window (default: last 20 %%)")
    ap.add_argument("--dpi", type=int, default=120)
    ap.add_argument("-o", "--output", required=True)
    args = ap.parse_args()
    truth = {}
    if args.measurements:
        data = np.genfromtxt(args.measurements, delimiter=",", names=True)
        truth = {n.upper(): (data[data.dtype.names[0]], data[n]) for n in data.dtype.names}
    with h5py.File(args.result, "r") as f:
        g = f[f"results/{args.subcase}/estimate"]
        t = g["time"][()]
        series = []
        for kind in ("params", "inputs"):
            if kind in g:
                for name in g[kind]:
                    series.append((name, g[kind][name][()], g[f"{kind}_sigma"][name][()]))
        sensors = [(n, ds.attrs.get("aae"), ds.attrs.get("mra"), int(ds.attrs.get("measured", 0))) for n, ds in g["sensors"].items()]
    zoom = args.zoom or (t[int(0.8 * len(t))], t[-1])
    fig, axes = plt.subplots(len(series) + 1, 2, figsize=(11, 3.2 * (len(series) + 1)), squeeze=False)
    for row, (name, value, sigma) in enumerate(series):
        for col, window in enumerate([(t[0], t[-1]), zoom]):
            ax = axes[row][col]
            keep = (t >= window[0]) & (t <= window[1])
            ax.fill_between(t[keep], (value - 3 * sigma)[keep], (value + 3 * sigma)[keep], color="C0", alpha=0.25, label="±3σ")
            ax.plot(t[keep], value[keep], "C0", lw=1, label=f"estimated {name}")
            if name.upper() in truth:
                tt, tv = truth[name.upper()]
                k = (tt >= window[0]) & (tt <= window[1])
                ax.plot(tt[k], tv[k], "k--", lw=1, label="true")
            ax.set_xlabel("t [s]")
            ax.set_title(f"{name}" + (" (zoom)" if col else ""))
            ax.legend(fontsize=8)
    ax = axes[-1][0]
    rated = [(n, a, m, meas) for n, a, m, meas in sensors if a is not None]
    x = np.arange(len(rated))
    ax.bar(x - 0.2, [a for _, a, _, _ in rated], 0.4, label="AAE")
    ax.bar(x + 0.2, [m for _, _, m, _ in rated], 0.4, label="MRA")
    ax.set_yscale("log")
    ax.set_xticks(x, [n + (" (meas.)" if meas else "") for n, _, _, meas in rated], rotation=45, ha="right", fontsize=8)
    ax.set_title("sensor errors (AAE vs MRA, thesis §8.6)")
    ax.legend(fontsize=8)
    axes[-1][1].axis("off")
    fig.tight_layout()
    fig.savefig(args.output, dpi=args.dpi)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
