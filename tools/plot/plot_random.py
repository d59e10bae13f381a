#!/usr/bin/env python3
"""Plot the output power spectral densities of a paraflex random response
(``/random/<sid>/<quantity>_psd``) to PNG, log-log, one curve per (grid, component) asked,
with its RMS and N0 in the legend.

    .venv/bin/python tools/plot/plot_random.py out.h5 -o psd.png [--sid 50]
        [--quantity acceleration] [--dof 2:1,1:1]   # GRID:component (1-6); default: every
                                                    # grid's largest-RMS component
"""
from __future__ import annotations

import argparse
from pathlib import Path

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("file", type=Path)
    ap.add_argument("-o", "--output", type=Path, required=True)
    ap.add_argument("--sid", help="RANDOM set id (default: the first one written)")
    ap.add_argument("--quantity", default="displacement", choices=["displacement", "velocity", "acceleration"])
    ap.add_argument("--dof", help="comma-separated GRID:component pairs")
    args = ap.parse_args()
    with h5py.File(args.file, "r") as f:
        sid = args.sid or sorted(f["random"].keys(), key=int)[0]
        g = f[f"random/{sid}"]
        q = args.quantity
        if f"{q}_psd" not in g:
            raise SystemExit(f"/random/{sid} has no {q}_psd: the subcases asked no {q.upper()}")
        hz = g["frequency_hz"][()]
        psd, rms, n0 = g[f"{q}_psd"][()], g[f"{q}_rms"][()], g[f"{q}_n0"][()]
        ids = list(g[f"{q}_grid_ids"][()])
    if args.dof:
        dofs = [tuple(int(x) for x in d.split(":")) for d in args.dof.split(",")]
    else:
        dofs = [(gid, int(np.argmax(rms[row])) + 1) for row, gid in enumerate(ids)]
    fig, ax = plt.subplots(figsize=(8, 5))
    for gid, comp in dofs:
        row = ids.index(gid)
        ax.loglog(hz, psd[:, row, comp - 1],
                  label=f"{gid}:{comp}  RMS {rms[row, comp - 1]:.4g}, N0 {n0[row, comp - 1]:.4g} Hz")
    ax.set_xlabel("frequency (Hz)")
    ax.set_ylabel(f"{q} PSD (unit²/Hz)")
    ax.set_title(f"{args.file.name}: RANDOM {sid}")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(args.output, dpi=120)


if __name__ == "__main__":
    main()
