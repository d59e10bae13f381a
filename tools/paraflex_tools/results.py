"""Reading paraflex's HDF5 result files (schema: docs, "HDF5 files") with h5py.

Names (outputs, inputs, sensors, parameters) are stored as HDF5 strings, which h5py returns as
``bytes`` or ``str`` depending on how they were written; :func:`texts` gives ``str`` either way.
"""
from __future__ import annotations

import os
from dataclasses import dataclass, field
from typing import Iterator

import h5py
import numpy as np


def texts(values) -> list[str]:
    """A string dataset or attribute as a list of ``str``."""
    return [v.decode() if isinstance(v, bytes) else str(v) for v in values]


def text(value) -> str:
    """A scalar string attribute as ``str``."""
    return value.decode() if isinstance(value, bytes) else str(value)


@dataclass
class Frf:
    """``/results/<subcase>/frf``: H[line, output, input] (complex) at ``frequency_hz``, and the
    parameter point of a pROM evaluation (empty for a full model)."""

    frequency_hz: np.ndarray
    H: np.ndarray
    outputs: list[str]
    inputs: list[str]
    params: dict[str, float] = field(default_factory=dict)

    def pair(self, output: str, input: str) -> np.ndarray:
        """H of one output and one input over the frequency lines."""
        return self.H[:, self.outputs.index(output), self.inputs.index(input)]


def read_frf(path: str | os.PathLike, subcase: str | int = 1) -> Frf:
    with h5py.File(path, "r") as f:
        g = f[f"results/{subcase}/frf"]
        params = dict(zip(texts(g.attrs.get("params", [])), g.attrs.get("values", [])))
        return Frf(g["frequency_hz"][()], g["H"][()], texts(g["outputs"][()]), texts(g["inputs"][()]), params)


def transient_series(group: h5py.Group, kind: str, name: str) -> np.ndarray:
    """One history of ``/results/<subcase>/transient``: ``kind`` ``sensors`` and a sensor name, or
    ``displacement``/``velocity``/``acceleration`` and an output name (e.g. ``71:3``)."""
    if kind == "sensors":
        return group["sensors"][name][()]
    outputs = texts(group["outputs"][()])
    if name not in outputs:
        raise KeyError(f"no output {name} (outputs: {', '.join(outputs)})")
    return group[kind][:, outputs.index(name)]


def grid_rows(f: h5py.File, group: h5py.Group, name: str) -> np.ndarray:
    """Grid ids of the rows of the node field ``name`` of ``group``: ``<name>_grid_ids`` when
    its request named a SET, else every grid (``/model/grid_ids``)."""
    rows = f"{name}_grid_ids"
    return group[rows][()] if rows in group else f["model/grid_ids"][()]


@dataclass
class Modes:
    """``/results/<subcase>/modal``: ``shapes[mode, row, component]`` (T1 T2 T3 R1 R2 R3, basic
    system) with the grid id of each row."""

    frequency_hz: np.ndarray
    grid_ids: np.ndarray
    shapes: np.ndarray

    def of_grid(self, grid: int) -> np.ndarray:
        """mode × 6 components of one grid."""
        rows = np.flatnonzero(self.grid_ids == grid)
        if len(rows) == 0:
            raise KeyError(f"grid {grid} is not in the mode shapes")
        return self.shapes[:, rows[0], :]


def read_modes(path: str | os.PathLike, subcase: str | int = 1) -> Modes:
    """Frequencies and mode shapes (the deck needs a DISPLACEMENT request) of a subcase."""
    with h5py.File(path, "r") as f:
        g = f[f"results/{subcase}/modal"]
        return Modes(g["frequency_hz"][()], grid_rows(f, g, "shapes"), g["shapes"][()])


def modal_frequencies(path: str | os.PathLike, subcase: str | int = 1) -> np.ndarray:
    """``/results/<subcase>/modal/frequency_hz``."""
    with h5py.File(path, "r") as f:
        return f[f"results/{subcase}/modal/frequency_hz"][()]


def subcases(path: str | os.PathLike) -> list[str]:
    """The subcase names under ``/results``, in numeric order."""
    with h5py.File(path, "r") as f:
        return sorted(f["results"].keys(), key=lambda s: (len(s), s)) if "results" in f else []


def _attributes(group: h5py.Group) -> dict[str, object]:
    """A group's attributes with strings decoded."""
    out: dict[str, object] = {}
    for key, value in group.attrs.items():
        if isinstance(value, (bytes, str)):
            out[key] = text(value)
        elif isinstance(value, np.ndarray) and value.dtype.kind in "OSU":
            out[key] = texts(value)
        else:
            out[key] = value
    return out


def _series(group: h5py.Group, name: str) -> dict[str, np.ndarray]:
    """Every dataset of the subgroup ``name`` of ``group`` (empty when it is absent)."""
    return {key: ds[()] for key, ds in group[name].items()} if name in group else {}


@dataclass
class Statics:
    """``/results/<subcase>/statics``: ``displacement[row, component]`` (T1 T2 T3 R1 R2 R3,
    basic) with the grid id of each row, SPC forces when requested, and the group's attributes."""

    grid_ids: np.ndarray
    displacement: np.ndarray
    spc_force: np.ndarray | None
    attrs: dict[str, object]

    def of_grid(self, grid: int) -> np.ndarray:
        """The six components of one grid."""
        rows = np.flatnonzero(self.grid_ids == grid)
        if len(rows) == 0:
            raise KeyError(f"grid {grid} is not in the static displacements")
        return self.displacement[rows[0]]


def read_statics(path: str | os.PathLike, subcase: str | int = 1) -> Statics:
    with h5py.File(path, "r") as f:
        g = f[f"results/{subcase}/statics"]
        spc = g["spc_force"][()] if "spc_force" in g else None
        return Statics(grid_rows(f, g, "displacement"), g["displacement"][()], spc, _attributes(g))


@dataclass
class Transient:
    """``/results/<subcase>/transient``: output times, SENSOR histories by name and, when
    stored, the displacement/velocity/acceleration histories of ``outputs`` (pROM) or of grids
    (full model, ``displacement[t, row, component]``)."""

    time: np.ndarray
    sensors: dict[str, np.ndarray]
    fields: dict[str, np.ndarray]
    outputs: list[str]
    attrs: dict[str, object]

    def output(self, kind: str, name: str) -> np.ndarray:
        """The history of one output DOF (``GRID:component``) of ``kind`` (displacement,
        velocity or acceleration) of a pROM transient."""
        if name not in self.outputs:
            raise KeyError(f"no output {name} (outputs: {', '.join(self.outputs)})")
        return self.fields[kind][:, self.outputs.index(name)]


def read_transient(path: str | os.PathLike, subcase: str | int = 1) -> Transient:
    with h5py.File(path, "r") as f:
        g = f[f"results/{subcase}/transient"]
        fields = {k: g[k][()] for k in ("displacement", "velocity", "acceleration") if k in g}
        outputs = texts(g["outputs"][()]) if "outputs" in g else []
        return Transient(g["time"][()], _series(g, "sensors"), fields, outputs, _attributes(g))


@dataclass
class Multibody:
    """``/results/<subcase>/fmb``: output times, MSENSOR histories by name, the drives' angle,
    rate, torque and power by JDRIVE id, the constraint residual and Newton iterations per step,
    and the group's attributes (method, coordinates, constraints, params, values)."""

    time: np.ndarray
    sensors: dict[str, np.ndarray]
    drives: dict[str, dict[str, np.ndarray]]
    constraint_residual: np.ndarray
    newton_iterations: np.ndarray
    attrs: dict[str, object]

    @property
    def parameters(self) -> dict[str, float]:
        """BODY.PMPAR → value of the run."""
        return dict(zip(self.attrs.get("params", []), np.atleast_1d(self.attrs.get("values", []))))


def read_multibody(path: str | os.PathLike, subcase: str | int = 1) -> Multibody:
    with h5py.File(path, "r") as f:
        g = f[f"results/{subcase}/fmb"]
        drives = {name: {k: d[()] for k, d in group.items()} for name, group in g["drives"].items()} \
            if "drives" in g else {}
        return Multibody(g["time"][()], _series(g, "sensors"), drives, g["constraint_residual"][()],
                         g["newton_iterations"][()], _attributes(g))


@dataclass
class Poses:
    """``/results/<subcase>/fmb/poses``: the static equilibria of a pose grid (``POSES = id``):
    ``values[pose, drive]`` (row-major over the axes, the first drive slowest), the JDRIVE ids
    of the axes, the axis lengths ``shape``, per pose whether it converged, its Newton
    iterations and residuals, the MSENSOR values by name, and the group's attributes."""

    values: np.ndarray
    drives: list[str]
    shape: tuple[int, ...]
    converged: np.ndarray
    iterations: np.ndarray
    force_residual: np.ndarray
    constraint_residual: np.ndarray
    sensors: dict[str, np.ndarray]
    attrs: dict[str, object]

    def axis(self, drive: str | int) -> np.ndarray:
        """The values of one drive's axis (JDRIVE id)."""
        k = self.drives.index(str(drive))
        grid = self.values.reshape(self.shape + (len(self.drives),))
        along = tuple(slice(None) if i == k else 0 for i in range(len(self.shape)))
        return grid[along + (k,)]

    def map(self, sensor: str) -> np.ndarray:
        """A sensor over the grid, shaped like the axes (NaN where a pose did not converge)."""
        return self.sensors[sensor].reshape(self.shape)


def read_poses(path: str | os.PathLike, subcase: str | int = 1) -> Poses:
    with h5py.File(path, "r") as f:
        g = f[f"results/{subcase}/fmb/poses"]
        return Poses(g["values"][()], texts(g["drives"][()]), tuple(int(n) for n in g["shape"][()]),
                     g["converged"][()].astype(bool), g["iterations"][()], g["force_residual"][()],
                     g["constraint_residual"][()], _series(g, "sensors"), _attributes(g))


@dataclass
class Estimate:
    """``/results/<subcase>/estimate``: filter times, parameter and input estimates with their σ,
    posterior sensor histories, innovations, and the group's attributes."""

    time: np.ndarray
    params: dict[str, np.ndarray]
    params_sigma: dict[str, np.ndarray]
    inputs: dict[str, np.ndarray]
    inputs_sigma: dict[str, np.ndarray]
    sensors: dict[str, np.ndarray]
    innovation: dict[str, np.ndarray]
    attrs: dict[str, object]


def read_estimate(path: str | os.PathLike, subcase: str | int = 1) -> Estimate:
    with h5py.File(path, "r") as f:
        g = f[f"results/{subcase}/estimate"]
        parts = ("params", "params_sigma", "inputs", "inputs_sigma", "sensors", "innovation")
        return Estimate(g["time"][()], *(_series(g, name) for name in parts), _attributes(g))


def walk(f: h5py.File) -> Iterator[tuple[str, str, object]]:
    """Every group, dataset and attribute of a file, sorted by path: ``(path, kind, value)``
    with kind ``group`` (value None), ``dataset`` (its data) or ``attribute`` (path
    ``<object>@<name>``)."""
    entries: list[tuple[str, str, object]] = []

    def visit(name: str, obj) -> None:
        if isinstance(obj, h5py.Dataset):
            entries.append((name, "dataset", obj[()]))
        else:
            entries.append((name, "group", None))
        for key, value in obj.attrs.items():
            entries.append((f"{name}@{key}", "attribute", value))

    visit("/", f)
    f.visititems(lambda name, obj: visit("/" + name, obj))
    return iter(sorted(entries, key=lambda e: e[0]))
