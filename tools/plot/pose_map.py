#!/usr/bin/env python3
"""Draw one MSENSOR of a two-drive pose grid (``/results/<subcase>/fmb/poses``, case control
``POSES = id``) as a 2-D map (pcolormesh) to PNG: the first drive's values along x, the
second's along y, in degrees for angles (``--radians`` keeps radians), poses without an
equilibrium left blank.

    .venv/bin/python tools/plot/pose_map.py arm_map.h5 TIPDEV -o tipdev.png [--subcase 1] [--scale 1e3 --unit mm]
"""
from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from paraflex_tools.results import read_poses  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("file", type=Path)
    ap.add_argument("sensor")
    ap.add_argument("-o", "--output", type=Path, help="PNG (default: <file stem>_<sensor>.png)")
    ap.add_argument("--subcase", default="1")
    ap.add_argument("--radians", action="store_true", help="label the axes in radians")
    ap.add_argument("--scale", type=float, default=1.0, help="factor on the sensor's values")
    ap.add_argument("--unit", default="", help="unit of the scaled values, for the colour bar")
    args = ap.parse_args()
    poses = read_poses(args.file, args.subcase)
    if len(poses.shape) != 2:
        raise SystemExit(f"{args.file}: the grid has {len(poses.shape)} drive(s); a map needs two")
    if args.sensor not in poses.sensors:
        raise SystemExit(f"{args.file}: no sensor {args.sensor} (sensors: {', '.join(sorted(poses.sensors))})")
    to_axis = (lambda v: v) if args.radians else np.degrees
    x, y = (to_axis(poses.axis(d)) for d in poses.drives)
    values = np.where(poses.converged.reshape(poses.shape), poses.map(args.sensor), np.nan) * args.scale
    fig, ax = plt.subplots(figsize=(5.5, 4.5))
    mesh = ax.pcolormesh(x, y, values.T, shading="nearest", cmap="viridis")
    unit = "rad" if args.radians else "deg"
    ax.set_xlabel(f"JDRIVE {poses.drives[0]} ({unit})")
    ax.set_ylabel(f"JDRIVE {poses.drives[1]} ({unit})")
    label = f"{args.sensor} ({args.unit})" if args.unit else args.sensor
    fig.colorbar(mesh, ax=ax, label=label)
    ax.set_title(f"{args.file.name}: {args.sensor} over {poses.shape[0]} x {poses.shape[1]} poses")
    fig.tight_layout()
    out = args.output or args.file.with_name(f"{args.file.stem}_{args.sensor}.png")
    fig.savefig(out, dpi=120)
    print(out)


if __name__ == "__main__":
    main()
