#!/usr/bin/env python3
"""Uniform-tension membrane patch of CQUAD4s with the drilling rotations free or held.

A plate 1 x 0.6 (t = 0.01, E = 1e11, nu = 0.25) held by u = 0 at the x = 0 grids (v = 0 at the
origin) and pulled by nodal FORCEs at x = 1 (60 kN, edge shares l/2 at the corners): the exact
field is u = 1e-4 x. Prints, per mesh and per PS (345: drilling rotation free, 3456: held), the
largest |u_x - 1e-4 x| and the tip's mean u_x relative to 1e-4 (docs/elements.md, "CQUAD4
membrane and drilling rotation": exact to round-off either way, since the element's edges are
linear in the corner translations). Not a test: the distorted-mesh version is
fe::shell_tests::membrane_tension_patch_with_free_drilling_rotations_is_exact.

    .venv/bin/python tools/bench/drilling_patch.py --paraflex target/release/paraflex
"""

import argparse
import os
import subprocess
import tempfile

import h5py
import numpy as np


def deck(nx, ny, ps):
    length, height, load = 1.0, 0.6, 60000.0
    lines = ["SOL 101", "CEND", "SPC = 1", "LOAD = 5", "DISPLACEMENT = ALL", "BEGIN BULK",
             "PSHELL,1,7,0.01", "MAT1,7,1.e11,,0.25"]

    def gid(i, j):
        return 1 + i * (ny + 1) + j

    for i in range(nx + 1):
        for j in range(ny + 1):
            lines.append("GRID,%d,,%r,%r,0.,,%s" % (gid(i, j), length * i / nx, height * j / ny, ps))
    eid = 1
    for i in range(nx):
        for j in range(ny):
            lines.append("CQUAD4,%d,1,%d,%d,%d,%d"
                         % (eid, gid(i, j), gid(i + 1, j), gid(i + 1, j + 1), gid(i, j + 1)))
            eid += 1
    for j in range(ny + 1):
        share = 0.5 if j in (0, ny) else 1.0
        lines.append("FORCE,5,%d,,%r,1.,0.,0." % (gid(nx, j), load / ny * share))
        lines.append("SPC1,1,1,%d" % gid(0, j))
    lines += ["SPC1,1,2,%d" % gid(0, 0), "ENDDATA"]
    return "\n".join(lines) + "\n"


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--paraflex", default="target/release/paraflex")
    args = ap.parse_args()
    binary = os.path.abspath(args.paraflex)
    print("| mesh | PS | max abs(u_x - 1e-4 x) / 1e-4 | tip mean u_x / 1e-4 |")
    print("|---|---|---|---|")
    with tempfile.TemporaryDirectory() as tmp:
        for nx, ny in ((3, 2), (6, 4), (12, 8), (24, 16)):
            for ps in ("345", "3456"):
                path = os.path.join(tmp, "patch.dat")
                with open(path, "w") as fh:
                    fh.write(deck(nx, ny, ps))
                out = os.path.join(tmp, "patch.h5")
                subprocess.run([binary, "run", path, "-o", out], check=True, capture_output=True)
                with h5py.File(out) as f:
                    u = f["results/1/statics/displacement"][:, 0]
                    x = f["model/xyz"][:, 0]
                error = np.abs(u - 1e-4 * x).max() / 1e-4
                tip = u[x > 1.0 - 1e-9].mean() / 1e-4
                print("| %d x %d | %s | %.3g | %.4f |" % (nx, ny, ps, error, tip))


if __name__ == "__main__":
    main()
