"""Picture of the Robolink model in its reference configuration (docs/img/robot_model.png):
the shell meshes of the flexible bodies placed as ``robot_bodies.inc`` places them, the rigid
solids of ``tools/robot/model.py`` (motor cylinders, L4 + M5 and EE boxes) as wireframes.

Run: ``.venv/bin/python tools/robot/picture.py``.
"""
from __future__ import annotations

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402

from model import (AXIS_DIR, AXIS_POINT, EE_BOX, L4_BOX, L4_GAP, LINKS, MESHES, MOTOR, REPO,  # noqa: E402
                   Z_L1, Z_M4, Z_M5, read_shell_mesh)

COLOURS = {"P": "0.8", "L1": "tab:blue", "L2R": "tab:orange", "L2L": "tab:orange",
           "L3R": "tab:green", "L3L": "tab:green"}


def cylinder(ax, centre, axis, r, h) -> None:
    a = np.asarray(axis, float)
    u = np.cross(a, [1.0, 0.0, 0.0] if abs(a[0]) < 0.9 else [0.0, 1.0, 0.0])
    u /= np.linalg.norm(u)
    v = np.cross(a, u)
    phi = np.linspace(0, 2 * np.pi, 25)
    for s in (-h / 2, h / 2):
        ring = centre + s * a + r * (np.outer(np.cos(phi), u) + np.outer(np.sin(phi), v))
        ax.plot(*ring.T, color="k", lw=0.6)
    for p in phi[::3]:
        line = np.array([centre + s * a + r * (np.cos(p) * u + np.sin(p) * v)
                         for s in (-h / 2, h / 2)])
        ax.plot(*line.T, color="k", lw=0.6)


def box(ax, lower, size) -> None:
    lo, hi = np.asarray(lower), np.asarray(lower) + np.asarray(size)
    for i in range(3):
        for a in (lo, hi):
            for b in (lo, hi):
                p, q = a.copy(), a.copy()
                p[i], q[i] = lo[i], hi[i]
                j, k = [m for m in range(3) if m != i]
                p[k] = q[k] = b[k]
                ax.plot(*np.array([p, q]).T, color="k", lw=0.6)


def main() -> None:
    fig = plt.figure(figsize=(7, 8))
    ax = fig.add_subplot(projection="3d")
    for _, name, _, mesh, placement, _ in LINKS:
        grids, shells = read_shell_mesh(MESHES / f"{mesh}.bdf")
        polys = [[placement.to_global(grids[g]) for g in nodes] for nodes in shells]
        if name == "P":            # the plate's middle only: the arm is what the picture shows
            polys = [p for p in polys if max(max(abs(x[0]), abs(x[1])) for x in p) < 0.35]
        ax.add_collection3d(Poly3DCollection(polys, facecolor=COLOURS[name], edgecolor="none",
                                             alpha=0.9))
    centres = {"M1": np.array([0.0, 0.0, Z_L1 / 2])} | {m: AXIS_POINT[m] for m in ("M2", "M3", "M4")}
    for m, (r, h) in MOTOR.items():
        cylinder(ax, centres[m], AXIS_DIR[m], r, h)
    lx, ly, _ = L4_BOX
    box(ax, [-lx / 2, -ly / 2, Z_M4 + L4_GAP], L4_BOX)
    ex, ey, _ = EE_BOX
    box(ax, [-ex / 2, -ey / 2, Z_M5], EE_BOX)
    ax.set_xlim(-0.4, 0.4)
    ax.set_ylim(-0.4, 0.4)
    ax.set_zlim(0.0, 1.35)
    ax.set_box_aspect((0.8, 0.8, 1.35))
    ax.view_init(elev=18, azim=-60)
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_zlabel("z (m)")
    ax.set_title("Robolink pFMB, reference configuration")
    fig.tight_layout()
    out = REPO / "docs" / "img" / "robot_model.png"
    fig.savefig(out, dpi=100)
    print(out)


if __name__ == "__main__":
    main()
