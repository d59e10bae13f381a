#!/usr/bin/env python3
"""Plot time histories written by paraflex (``/results/<subcase>/transient``) to PNG, several
files overlaid (e.g. full model, ROM and pROM; thesis Fig. 3.14), with an inset zooming on a
time window.

    .venv/bin/python tools/plot/plot_transient.py full.h5 prom.h5 -o th.png \
        [--series sensors/D71 displacement:71:3] [--zoom 0.010 0.014] [--labels full pROM]

A series is ``sensors/<name>`` or ``displacement|velocity|acceleration:<output name>`` (pROM
input-DOF outputs, e.g. ``displacement:71:3``); give one for all files or one per file (a full
model's sensor against a pROM's input-DOF output). Default: each file's first sensor, else its
first displacement output.
"""
from __future__ import annotations

import argparse
from pathlib import Path

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
from mpl_toolkits.axes_grid1.inset_locator import inset_axes, mark_inset  # noqa: E402
import numpy as np  # noqa: E402

from paraflex_tools.results import texts, transient_series  # noqa: E402


def read(path: Path, subcase: str, series: str | None):
    with h5py.File(path, "r") as f:
        g = f[f"results/{subcase}/transient"]
        t = g["time"][:]
        if series is None:
            series = f"sensors/{sorted(g['sensors'])[0]}" if "sensors" in g else "displacement:" + texts(g["outputs"][:1])[0]
        kind, name = series.split("/", 1) if series.startswith("sensors/") else series.split(":", 1)
        try:
            return t, transient_series(g, kind, name), series
        except KeyError as e:
            raise SystemExit(f"{path}: {e.args[0]}") from None


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("files", type=Path, nargs="+")
    ap.add_argument("-o", "--output", type=Path, required=True)
    ap.add_argument("--subcase", default="1")
    ap.add_argument("--series", nargs="*", default=None)
    ap.add_argument("--labels", nargs="*", default=None)
    ap.add_argument("--zoom", type=float, nargs=2, default=None, metavar=("T0", "T1"), help="inset time window, s")
    a = ap.parse_args()
    labels = a.labels or [p.stem for p in a.files]
    fig, ax = plt.subplots(figsize=(9, 4.2))
    curves = []
    wanted = a.series or [None]
    if len(wanted) not in (1, len(a.files)):
        raise SystemExit("--series: give one series, or one per file")
    names = []
    for k, (path, label) in enumerate(zip(a.files, labels)):
        t, y, series = read(path, a.subcase, wanted[k % len(wanted)])
        names.append(series)
        curves.append((t, y, label))
        ax.plot(t, y, lw=1.0, ls=["-", "--", ":", "-."][k % 4], label=label)
    ax.set_xlabel("time [s]")
    ax.set_ylabel(" / ".join(dict.fromkeys(names)))
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper right")
    if a.zoom:
        t0, t1 = a.zoom
        ins = inset_axes(ax, width="34%", height="38%", loc="lower left", borderpad=1.2)
        lo, hi = np.inf, -np.inf
        for k, (t, y, _) in enumerate(curves):
            m = (t >= t0) & (t <= t1)
            ins.plot(t[m], y[m], lw=1.0, ls=["-", "--", ":", "-."][k % 4])
            if m.any():
                lo, hi = min(lo, y[m].min()), max(hi, y[m].max())
        ins.set_xlim(t0, t1)
        if np.isfinite(lo):
            pad = 0.05 * (hi - lo or 1.0)
            ins.set_ylim(lo - pad, hi + pad)
        ins.tick_params(labelsize=7)
        ins.xaxis.set_major_locator(plt.MaxNLocator(4))
        mark_inset(ax, ins, loc1=2, loc2=4, fc="none", ec="0.5")
    fig.subplots_adjust(left=0.09, right=0.98, bottom=0.12, top=0.95)
    fig.savefig(a.output, dpi=130)
    print(f"wrote {a.output}")


if __name__ == "__main__":
    main()
