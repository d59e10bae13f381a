#!/usr/bin/env python3
"""Check the XDMF files of a paraflex output against its HDF5 file, reading them as users do.

``check_xdmf.py OUT.h5`` reads ``OUT.xdmf`` with ``meshio.read`` and every time series
``OUT_<subcase>_<kind>.xdmf`` with meshio's ``TimeSeriesReader`` (mesh and number of steps),
then resolves the step fields (XDMF 3 hyperslab references, which meshio does not read) with
h5py, and compares with the HDF5 arrays for exact equality: point coordinates, element ids,
static displacements, the number of steps (modes, output times) and their time values, and
the displacement of the first, middle and last step. Prints one line per file; exits 1 at
the first mismatch.
"""
from __future__ import annotations

import argparse
import re
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import h5py
import meshio
import numpy as np
from meshio.xdmf import TimeSeriesReader


class Mismatch(Exception):
    pass


def expect(ok: bool, what: str) -> None:
    if not ok:
        raise Mismatch(what)


def drawn_blocks(h5: h5py.File) -> list[str]:
    """Element blocks in the XDMF cell order (the order of /model/elements, as written)."""
    return [card for card in h5["model/elements"] if len(h5[f"model/elements/{card}/ids"]) > 0]


def check_model(xdmf: Path, h5: h5py.File) -> str:
    mesh = meshio.read(xdmf)
    expect(np.array_equal(mesh.points, h5["model/xyz"][()]), f"{xdmf.name}: points differ from /model/xyz")
    ids = np.concatenate([c for c in mesh.cell_data["element_id"]])
    cards = [c for c in drawn_blocks(h5) if len(h5[f"model/elements/{c}/connectivity"].shape) == 2]
    stored = np.concatenate([h5[f"model/elements/{c}/ids"][()] for c in cards])
    expect(np.array_equal(np.sort(ids), np.sort(stored)), f"{xdmf.name}: element ids differ")
    statics = 0
    for name, values in mesh.point_data.items():
        subcase = name.removeprefix("displacement_")
        expect(np.array_equal(values, h5[f"results/{subcase}/statics/displacement"][()]),
               f"{xdmf.name}: {name} differs from the HDF5 array")
        statics += 1
    return f"{xdmf.name}: meshio: {len(mesh.points)} points, {len(ids)} cells, {statics} static displacement(s)"


def resolve(item: ET.Element, folder: Path) -> np.ndarray:
    """The values of an HDF ``DataItem``, ``file:dataset`` or ``file:dataset|start:stride:count:shape``."""
    reference, *slab = item.text.strip().split("|")
    name, dataset = reference.split(":")
    with h5py.File(folder / name, "r") as f:
        data = f[dataset]
        if not slab:
            return data[()]
        start, stride, count, shape = ([int(v) for v in part.split()] for part in slab[0].split(":"))
        expect(list(data.shape) == shape, f"{dataset}: shape {data.shape}, the XDMF says {shape}")
        index = tuple(slice(b, b + s * c, s) for b, s, c in zip(start, stride, count))
        return data[index]


def check_series(xdmf: Path, h5: h5py.File) -> str:
    stem, subcase, kind = xdmf.stem.rsplit("_", 2)
    with TimeSeriesReader(xdmf) as reader:
        points, _cells = reader.read_points_cells()
        steps = reader.num_steps
    expect(np.array_equal(points, h5["model/xyz"][()]), f"{xdmf.name}: points differ from /model/xyz")
    group = h5[f"results/{subcase}/{'modal' if kind == 'modes' else kind}"]
    if kind == "modes":
        field, times = group["shapes"][()], np.arange(1, len(group["frequency_hz"]) + 1, dtype=float)
    elif kind == "transient":
        field, times = group["displacement"][()], group["time"][()]
    else:
        field, times = group["displacement"][()][None], np.zeros(1)
    expect(steps == len(times), f"{xdmf.name}: {steps} steps, the HDF5 file has {len(times)}")
    grids = ET.parse(xdmf).getroot().find("Domain/Grid").findall("Grid")
    for i in sorted({0, steps // 2, steps - 1}):
        time = float(grids[i].find("Time").get("Value"))
        expect(time == times[i], f"{xdmf.name}: step {i} at time {time}, the HDF5 file has {times[i]}")
        attributes = {a.get("Name"): a for a in grids[i].findall("Attribute")}
        u = resolve(attributes["displacement"].find("DataItem"), xdmf.parent).reshape(-1, 3)
        expect(np.array_equal(u, field[i][:, :3]), f"{xdmf.name}: displacement of step {i} differs")
    return f"{xdmf.name}: meshio: {len(points)} points, {steps} steps; displacements equal"


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("h5", type=Path, help="paraflex output file (OUT.h5)")
    args = parser.parse_args(argv)
    try:
        with h5py.File(args.h5, "r") as h5:
            print(check_model(args.h5.with_suffix(".xdmf"), h5))
            pattern = re.compile(re.escape(args.h5.stem) + r"_\d+_(statics|modes|transient)\.xdmf")
            for series in sorted(args.h5.parent.iterdir()):
                if pattern.fullmatch(series.name):
                    print(check_series(series, h5))
    except Mismatch as e:
        print(f"mismatch: {e}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
