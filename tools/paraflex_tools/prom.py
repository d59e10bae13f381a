"""Evaluating a pROM artifact (``/prom``, written by ``SOL PROM``) at a parameter point in numpy.

The artifact keeps the affine split of thesis eq. 3.31–3.32: M_r(p) = Σ_i f_i(p) M_r^i,
K_r(p) = Σ_i f_i(p) K_r^i, C_r(p) = α M_r(p) + β K_r(p). Each f_i is stored in the ``functions``
attribute (JSON) as a coefficient kind of the element library (E, ρ, Lamé λ and μ, plane-stress
λ*, the five angle-ply functions of eq. 3.18, ply-thickness powers of eq. 3.20–3.22, lumped
values) with its fixed inputs and the parameters that drive them. :class:`Prom` reads the
components once and sums them for any p, so a plot script or a notebook can sweep a parameter
without running paraflex; the solver's own evaluation is ``paraflex run`` with ``ROM =`` and
``PVAL``, against which ``tools/tests/test_prom.py`` checks this one.
"""
from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass

import h5py
import numpy as np
import scipy.linalg

from paraflex_tools.results import texts

#: Fields of the stored inputs of a coefficient (``CoefficientValues`` in the solver).
_INPUT_FIELD = {"E": "e", "Nu": "nu", "Rho": "rho", "ThetaDeg": "theta_deg", "H": "h", "Lumped": "lumped"}


def coefficient_value(kind: str, v: dict[str, float]) -> float:
    """f of one coefficient kind at inputs ``v`` (keys e, nu, rho, theta_deg, h, lumped)."""
    c, s = math.cos(math.radians(v["theta_deg"])), math.sin(math.radians(v["theta_deg"]))
    e, nu = v["e"], v["nu"]
    values = {
        "Constant": lambda: 1.0,
        "E": lambda: e,
        "Rho": lambda: v["rho"],
        "Lambda": lambda: e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)),
        "Mu": lambda: e / (2.0 * (1.0 + nu)),
        "LambdaPlaneStress": lambda: e * nu / (1.0 - nu * nu),
        "Cos4": lambda: c**4,
        "Sin4": lambda: s**4,
        "Cos2Sin2": lambda: c * c * s * s,
        "CosSin3": lambda: c * s**3,
        "Cos3Sin": lambda: c**3 * s,
        "H": lambda: v["h"],
        "H2": lambda: v["h"] ** 2,
        "H3": lambda: v["h"] ** 3,
        "Lumped": lambda: v["lumped"],
    }
    if kind not in values:
        raise ValueError(f"unknown coefficient kind {kind!r} (known: {', '.join(values)})")
    return values[kind]()


@dataclass
class AffineFunction:
    """One f_i(p): a coefficient kind, its fixed inputs and (input, parameter index) pairs."""

    kind: str
    fixed: dict[str, float]
    driven_by: list[tuple[str, int]]

    def value(self, p: np.ndarray) -> float:
        inputs = dict(self.fixed)
        for name, j in self.driven_by:
            inputs[_INPUT_FIELD[name]] = float(p[j])
        return coefficient_value(self.kind, inputs)


@dataclass
class Parameter:
    name: str
    low: float
    high: float
    nominal: float


class Prom:
    """A pROM artifact in memory: parameters, affine functions, reduced components, damping,
    input shapes S_r and sensor rows H_r."""

    def __init__(self, path: str | os.PathLike):
        with h5py.File(path, "r") as f:
            g = f["prom"]
            names = texts(g.attrs["params"])
            ranges = np.asarray(g.attrs["ranges"], dtype=float).reshape(len(names), 2)
            nominal = np.asarray(g.attrs["nominal"], dtype=float)
            self.parameters = [Parameter(n, lo, hi, x) for n, (lo, hi), x in zip(names, ranges, nominal)]
            self.functions = [
                AffineFunction(entry["coefficient"], entry["fixed"], [tuple(d) for d in entry["driven_by"]])
                for entry in json.loads(g.attrs["functions"])
            ]
            count = len(self.functions)
            self.stiffness = np.stack([g[f"K/{i}"][()] for i in range(count)])
            self.mass = np.stack([g[f"M/{i}"][()] for i in range(count)])
            self.alpha = float(g["damping"].attrs["alpha"])
            self.beta = float(g["damping"].attrs["beta"])
            self.input_names = texts(g["inputs/names"][()]) if "inputs" in g else []
            self.input_shapes = g["inputs/S_r"][()] if "inputs" in g else np.zeros((self.size, 0))
            if "sensors" in g:
                self.sensor_names = texts(g["sensors/names"][()])
                self.sensor_kinds = texts(g["sensors/kind"][()])
                self.sensor_rows = g["sensors/H_r"][()]
            else:
                self.sensor_names, self.sensor_kinds = [], []
                self.sensor_rows = np.zeros((0, self.size))

    @property
    def size(self) -> int:
        """n_red, the number of reduced coordinates."""
        return self.stiffness.shape[1]

    @property
    def parameter_names(self) -> list[str]:
        return [p.name for p in self.parameters]

    def point(self, values: dict[str, float] | None = None) -> np.ndarray:
        """The parameter vector: the nominal values, overridden by ``values`` (name → value).
        A name the pROM does not have is an error; a value outside the box is allowed
        (extrapolation), as in the solver."""
        p = np.array([q.nominal for q in self.parameters])
        for name, value in (values or {}).items():
            if name not in self.parameter_names:
                raise KeyError(f"no parameter {name} (the pROM has {', '.join(self.parameter_names)})")
            p[self.parameter_names.index(name)] = value
        return p

    def coefficients(self, values: dict[str, float] | None = None) -> np.ndarray:
        """f_i(p) of every affine component."""
        p = self.point(values)
        return np.array([fn.value(p) for fn in self.functions])

    def matrices(self, values: dict[str, float] | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """K_r(p), M_r(p), C_r(p) (eq. 3.31–3.32, Rayleigh damping)."""
        f = self.coefficients(values)
        stiffness = np.tensordot(f, self.stiffness, axes=1)
        mass = np.tensordot(f, self.mass, axes=1)
        return stiffness, mass, self.alpha * mass + self.beta * stiffness

    def frequencies(self, values: dict[str, float] | None = None) -> np.ndarray:
        """Undamped natural frequencies [Hz] of K_r(p) φ = ω² M_r(p) φ, ascending (a negative
        round-off eigenvalue gives a negative frequency, as the solver reports it)."""
        stiffness, mass, _ = self.matrices(values)
        eigenvalues = scipy.linalg.eigh(stiffness, mass, eigvals_only=True)
        return np.sign(eigenvalues) * np.sqrt(np.abs(eigenvalues)) / (2.0 * math.pi)

    def frf(self, frequency_hz, values: dict[str, float] | None = None) -> np.ndarray:
        """H[line, sensor, input] of the stored sensors to unit forces at the stored inputs:
        H_r (K − ω² M + iω C)⁻¹ S_r, times iω for a VEL sensor and −ω² for an ACCEL sensor."""
        stiffness, mass, damping = self.matrices(values)
        scale = {"DISP": lambda w: 1.0, "STRAIN": lambda w: 1.0, "VEL": lambda w: 1j * w, "ACCEL": lambda w: -w * w}
        lines = []
        for hz in np.atleast_1d(frequency_hz):
            w = 2.0 * math.pi * hz
            response = np.linalg.solve(stiffness - w * w * mass + 1j * w * damping, self.input_shapes)
            rows = np.array([scale[kind](w) for kind in self.sensor_kinds])[:, None] * self.sensor_rows
            lines.append(rows @ response)
        return np.array(lines)

    def response(self, time: np.ndarray, forces: np.ndarray, values: dict[str, float] | None = None) -> np.ndarray:
        """Sensor histories (time × sensor) from rest under forces at the stored inputs
        (time × input), linear between the samples, computed exactly: the first-order-hold
        transition of ẋ = A x + B f with x = [q, q̇] over each interval, from the matrix
        exponential of the augmented system (no time-integration error, unlike the solver's
        integrators, so measurements made with it are independent of them). ``time`` must be
        uniformly spaced. DISP and STRAIN sensors read q, VEL q̇, ACCEL q̈ = M⁻¹(S f − K q − C q̇).
        """
        stiffness, mass, damping = self.matrices(values)
        n, m = self.size, self.input_shapes.shape[1]
        steps = np.diff(time)
        if len(time) < 2 or not np.allclose(steps, steps[0], rtol=1e-9, atol=0.0):
            raise ValueError("response: the times must be uniformly spaced")
        h = steps[0]
        inverse_mass = np.linalg.inv(mass)
        a = np.block([[np.zeros((n, n)), np.eye(n)], [-inverse_mass @ stiffness, -inverse_mass @ damping]])
        b = np.vstack([np.zeros((n, m)), inverse_mass @ self.input_shapes])
        augmented = np.zeros((2 * n + 2 * m, 2 * n + 2 * m))
        augmented[: 2 * n, : 2 * n] = a * h
        augmented[: 2 * n, 2 * n : 2 * n + m] = b * h
        augmented[2 * n : 2 * n + m, 2 * n + m :] = np.eye(m)
        transition = scipy.linalg.expm(augmented)
        phi = transition[: 2 * n, : 2 * n]
        hold = transition[: 2 * n, 2 * n : 2 * n + m]
        ramp = transition[: 2 * n, 2 * n + m :]
        forces = np.asarray(forces, dtype=float).reshape(len(time), m)
        states = np.zeros((len(time), 2 * n))
        for k in range(len(time) - 1):
            states[k + 1] = phi @ states[k] + hold @ forces[k] + ramp @ (forces[k + 1] - forces[k])
        q, v = states[:, :n], states[:, n:]
        acceleration = (forces @ self.input_shapes.T - q @ stiffness.T - v @ damping.T) @ inverse_mass.T
        by_kind = {"DISP": q, "STRAIN": q, "VEL": v, "ACCEL": acceleration}
        return np.column_stack([by_kind[kind] @ row for kind, row in zip(self.sensor_kinds, self.sensor_rows)])
