#!/usr/bin/env python3
"""Plot FRFs written by paraflex (``/results/<subcase>/frf``) to PNG: |H| (log) and phase over
frequency, one curve per (output, input) pair, several files overlaid (e.g. pROMs at different
PVAL, or a pROM against another model).

    .venv/bin/python tools/plot/plot_frf.py out1.h5 [out2.h5 ...] -o frf.png [--subcase 1]
        [--pair 13:3,13:3]   # output,input names; default: every pair of the first file
"""
from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from paraflex_tools.results import read_frf  # noqa: E402


def read(path: Path, subcase: str):
    frf = read_frf(path, subcase)
    return frf.frequency_hz, frf.H, frf.outputs, frf.inputs, frf.params


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("files", nargs="+", type=Path)
    ap.add_argument("-o", "--output", type=Path, required=True)
    ap.add_argument("--subcase", default="1")
    ap.add_argument("--pair", action="append", default=[], help="OUTPUT,INPUT names (repeatable)")
    args = ap.parse_args()
    fig, (ax_mag, ax_ph) = plt.subplots(2, 1, sharex=True, figsize=(8, 6), gridspec_kw={"height_ratios": [3, 1]})
    first_pairs = None
    for path in args.files:
        hz, h, outputs, inputs, values = read(path, args.subcase)
        pairs = [tuple(p.split(",")) for p in args.pair] or first_pairs or [(o, i) for o in outputs for i in inputs]
        first_pairs = pairs
        label_values = ", ".join(f"{k} = {v:.4g}" for k, v in values.items())
        for o, i in pairs:
            hij = h[:, outputs.index(o), inputs.index(i)]
            label = f"{path.stem}: {o} / {i}" + (f" ({label_values})" if label_values else "")
            ax_mag.semilogy(hz, np.abs(hij), label=label)
            ax_ph.plot(hz, np.degrees(np.angle(hij)))
    ax_mag.set_ylabel("|H| (receptance)")
    ax_ph.set_ylabel("phase [deg]")
    ax_ph.set_xlabel("frequency [Hz]")
    ax_mag.legend(fontsize=7)
    ax_mag.grid(True, which="both", alpha=0.3)
    ax_ph.grid(True, alpha=0.3)
    fig.tight_layout()
    args.output.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.output, dpi=110)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
