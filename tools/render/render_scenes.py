#!/usr/bin/env python3
"""Render the scene meshes and a few mode shapes to PNG (docs/img/), for the README and
docs/scenes.md.

    .venv/bin/python tools/render/render_scenes.py                      # every committed mesh include
    .venv/bin/python tools/render/render_scenes.py --scene fourbar      # one scene
    .venv/bin/python tools/render/render_scenes.py --modes decks/fourbar/coupler_free.dat [--count 3]
    .venv/bin/python tools/render/render_scenes.py --h5 out.h5 --name coupler_free [--count 3]

Meshes: every ``meshes/<scene>/<component>.bdf`` (not the ``_rbe``/``_spc`` includes) is read
with pyNastran and drawn as a matplotlib 3-D PolyCollection of its shell elements and of the
boundary faces of its solids (faces that belong to one element only) → docs/img/<scene>_<component>.png.

Mode shapes: from a paraflex HDF5 file with ``/results/1/modal/shapes`` (docs/hdf5-schema.md;
the deck needs a DISPLACEMENT request). ``--modes DECK`` makes that file: it copies the deck to a
temp dir with absolute INCLUDE paths and ``DISPLACEMENT(PLOT) = ALL`` after CEND, runs
``paraflex run`` (``--paraflex``, default $CARGO_TARGET_DIR/release/paraflex or
target/release/paraflex), and draws the first ``--count`` elastic modes (f > 1 Hz) deformed,
coloured by displacement magnitude → docs/img/<deck stem>_mode<k>.png.
"""
from __future__ import annotations

import argparse
import re
import sys
import tempfile
from pathlib import Path

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from mpl_toolkits.mplot3d.art3d import Poly3DCollection  # noqa: E402
from pyNastran.bdf.bdf import BDF  # noqa: E402

from paraflex_tools.results import read_modes  # noqa: E402
from paraflex_tools.runner import default_binary, run_checked  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
OUT = REPO / "docs" / "img"
SCENES = ["plates", "fourbar", "robot", "blade"]

# faces of the solids as corner positions (Nastran node order); tet10 uses its 4 corners
SOLID_FACES = {
    8: [(0, 3, 2, 1), (4, 5, 6, 7), (0, 1, 5, 4), (1, 2, 6, 5), (2, 3, 7, 6), (3, 0, 4, 7)],
    6: [(0, 2, 1), (3, 4, 5), (0, 1, 4, 3), (1, 2, 5, 4), (2, 0, 3, 5)],
    4: [(0, 2, 1), (0, 1, 3), (1, 2, 3), (2, 0, 3)],
}


def boundary_faces(shells: list[list[int]], solids: list[list[int]]) -> list[tuple[int, ...]]:
    """Shell elements as they are, plus the solid faces that belong to one element only."""
    count: dict[tuple[int, ...], list] = {}
    for conn in solids:
        corners = conn[:4] if len(conn) == 10 else conn
        for face in SOLID_FACES[len(corners)]:
            nodes = tuple(corners[i] for i in face)
            key = tuple(sorted(nodes))
            count.setdefault(key, [0, nodes])[0] += 1
    return [tuple(s) for s in shells] + [nodes for n, nodes in count.values() if n == 1]


def draw(xyz: np.ndarray, faces, path: Path, title: str, colour=None) -> None:
    """One PNG of the faces (rows of xyz), equal axis scale, optional per-face colour values."""
    fig = plt.figure(figsize=(6.4, 3.6), dpi=90)
    ax = fig.add_subplot(projection="3d")
    polys = [xyz[list(f)] for f in faces]
    if colour is None:
        pc = Poly3DCollection(polys, facecolor="#9ab8d8", edgecolor="#2b3f57", linewidths=0.15)
    else:
        pc = Poly3DCollection(polys, cmap="viridis", edgecolor="none")
        pc.set_array(np.asarray(colour))
    ax.add_collection3d(pc)
    lo, hi = xyz.min(axis=0), xyz.max(axis=0)
    span = hi - lo
    big = span.max()
    ax.set_xlim(lo[0], hi[0] if span[0] > 0 else lo[0] + big * 0.05)
    ax.set_ylim(lo[1], hi[1] if span[1] > 0 else lo[1] + big * 0.05)
    ax.set_zlim(lo[2], hi[2] if span[2] > 0 else lo[2] + big * 0.05)
    ax.set_box_aspect(np.maximum(span, 0.05 * big))
    ax.set_proj_type("ortho")
    ax.view_init(elev=25, azim=-60)
    ax.set_axis_off()
    ax.set_title(title, fontsize=9)
    fig.subplots_adjust(0, 0, 1, 0.93)
    path.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(path, dpi=90)
    plt.close(fig)
    print(f"{path.relative_to(REPO)} ({path.stat().st_size // 1024} KB)")


def render_include(path: Path, scene: str) -> None:
    bdf = BDF(debug=None)
    bdf.read_bdf(str(path), xref=False, punch=True, validate=False)
    ids = sorted(bdf.nodes)
    row = {nid: i for i, nid in enumerate(ids)}
    xyz = np.array([bdf.nodes[n].xyz for n in ids], dtype=float)
    shells, solids = [], []
    for e in bdf.elements.values():
        conn = [row[n] for n in e.node_ids]
        (shells if e.type in ("CQUAD4", "CTRIA3") else solids).append(conn)
    faces = boundary_faces(shells, solids)
    draw(xyz, faces, OUT / f"{scene}_{path.stem}.png",
         f"{scene}/{path.name}: {len(ids)} grids, {len(bdf.elements)} elements")


def run_with_shapes(deck: Path, paraflex: Path, tmp: Path) -> Path:
    """Copy ``deck`` with absolute INCLUDEs and a DISPLACEMENT request, run it, return the .h5."""
    text = deck.read_text()
    text = re.sub(r"INCLUDE\s+'([^']+)'", lambda m: f"INCLUDE '{(deck.parent / m.group(1)).resolve()}'", text)
    text = re.sub(r"(?im)^CEND\s*$", "CEND\nDISPLACEMENT(PLOT) = ALL", text, count=1)
    copy, out = tmp / deck.name, tmp / (deck.stem + ".h5")
    copy.write_text(text)
    run_checked(copy, out, paraflex)
    return out


def render_modes(h5: Path, name: str, count: int) -> None:
    with h5py.File(h5, "r") as f:
        xyz = f["model/xyz"][()]
        shells, solids = [], []
        for card, group in f["model/elements"].items():
            if card in ("CQUAD4", "CTRIA3"):
                shells += group["connectivity"][()].tolist()
            elif card in ("CHEXA", "CPENTA", "CTETRA", "CTETRA10"):
                solids += group["connectivity"][()].tolist()
        modal = f["results/1/modal"]
        if "shapes" not in modal:
            sys.exit(f"{h5}: no /results/1/modal/shapes (the deck needs a DISPLACEMENT request)")
        modes = read_modes(h5)
        freqs, shapes = modes.frequency_hz, modes.shapes
        faces = boundary_faces(shells, solids)
        elastic = [k for k, fk in enumerate(freqs) if fk > 1.0][:count]
        size = np.ptp(xyz, axis=0).max()
        for k in elastic:
            u = shapes[k][:, :3]
            mag = np.linalg.norm(u, axis=1)
            deformed = xyz + u * (0.1 * size / mag.max())
            colour = [mag[list(fc)].mean() for fc in faces]
            draw(deformed, faces, OUT / f"{name}_mode{k + 1}.png",
                 f"{name}: mode {k + 1}, {freqs[k]:.1f} Hz (|u| colour, scaled)", colour)


def main() -> None:
    ap = argparse.ArgumentParser(description="render scene meshes and mode shapes to docs/img/")
    ap.add_argument("--scene", action="append", choices=SCENES, help="scenes to render (default: all)")
    ap.add_argument("--modes", type=Path, action="append", default=[], help="deck to run and draw modes of")
    ap.add_argument("--h5", type=Path, help="existing HDF5 result with mode shapes")
    ap.add_argument("--name", help="image name prefix for --h5 (default: file stem)")
    ap.add_argument("--count", type=int, default=3, help="elastic modes to draw (default 3)")
    ap.add_argument("--paraflex", type=Path, default=default_binary())
    args = ap.parse_args()
    if args.h5:
        render_modes(args.h5, args.name or args.h5.stem, args.count)
    for deck in args.modes:
        with tempfile.TemporaryDirectory() as tmp:
            render_modes(run_with_shapes(deck.resolve(), args.paraflex, Path(tmp)), deck.stem, args.count)
    if args.h5 or args.modes:
        return
    for scene in args.scene or SCENES:
        for path in sorted((REPO / "meshes" / scene).glob("*.bdf")):
            if not path.stem.endswith(("_rbe", "_spc")):
                render_include(path, scene)


if __name__ == "__main__":
    main()
