#!/usr/bin/env python3
"""Write a load signal as CSV (header ``time,<name>``) for a TABLEF card.

    .venv/bin/python tools/signals/make_signal.py sine -o sine.csv --freq 20 --amp 1 --duration 1 --dt 1e-4
    .venv/bin/python tools/signals/make_signal.py random -o rnd.csv --band 10 200 --rms 1 --seed 7 \
        --duration 1 --dt 1e-4

``sine``: amp · sin(2π f t + phase). ``random``: band-limited Gaussian noise, seeded (the same
seed gives the same file on every machine): white noise from numpy's PCG64 generator, filtered
in the frequency domain to [f_lo, f_hi] (brick-wall on the FFT of the whole record), scaled to
the requested RMS. ``--fade T`` multiplies the first T seconds by a raised cosine
(0.5 − 0.5 cos(πt/T)) so the signal starts from 0 with zero slope: a force that jumps at t = 0
excites every mode of a full model (the drive-point acceleration then carries content far
above the band, which a reduced model cannot have). Both start at t = 0; the deck reads them with e.g.
``TABLEF,9,'rnd.csv',time,force`` (column names are case-insensitive).
"""
from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np


def sine(t: np.ndarray, freq: float, amp: float, phase_deg: float) -> np.ndarray:
    return amp * np.sin(2.0 * np.pi * freq * t + np.radians(phase_deg))


def band_random(n: int, dt: float, lo: float, hi: float, rms: float, seed: int) -> np.ndarray:
    if not (0.0 <= lo < hi):
        raise SystemExit(f"band: need 0 <= f_lo < f_hi, got {lo}, {hi}")
    nyquist = 0.5 / dt
    if hi > nyquist:
        raise SystemExit(f"band: f_hi = {hi} Hz above the Nyquist frequency {nyquist} Hz of dt = {dt}")
    white = np.random.Generator(np.random.PCG64(seed)).standard_normal(n)
    spectrum = np.fft.rfft(white)
    f = np.fft.rfftfreq(n, dt)
    spectrum[(f < lo) | (f > hi)] = 0.0
    y = np.fft.irfft(spectrum, n)
    r = np.sqrt(np.mean(y * y))
    if r == 0.0:
        raise SystemExit("band: no FFT line falls in the band (record too short?)")
    return y * (rms / r)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("kind", choices=["sine", "random"])
    ap.add_argument("-o", "--output", type=Path, required=True)
    ap.add_argument("--duration", type=float, default=1.0, help="s")
    ap.add_argument("--dt", type=float, default=1e-4, help="sample spacing, s")
    ap.add_argument("--name", default="force", help="header of the value column")
    ap.add_argument("--freq", type=float, default=10.0, help="sine frequency, Hz")
    ap.add_argument("--amp", type=float, default=1.0, help="sine amplitude")
    ap.add_argument("--phase", type=float, default=0.0, help="sine phase, degrees")
    ap.add_argument("--band", type=float, nargs=2, default=[0.0, 100.0], metavar=("F_LO", "F_HI"), help="random band, Hz")
    ap.add_argument("--rms", type=float, default=1.0, help="random RMS")
    ap.add_argument("--seed", type=int, default=0, help="random seed")
    ap.add_argument("--fade", type=float, default=0.0, help="raised-cosine fade-in length, s (0: none)")
    a = ap.parse_args()
    if not (a.dt > 0 and a.duration > 0):
        raise SystemExit("--dt and --duration must be positive")
    n = int(round(a.duration / a.dt)) + 1
    t = np.arange(n) * a.dt
    y = sine(t, a.freq, a.amp, a.phase) if a.kind == "sine" else band_random(n, a.dt, a.band[0], a.band[1], a.rms, a.seed)
    if a.fade < 0:
        raise SystemExit("--fade must be >= 0")
    if a.fade > 0:
        ramp = t < a.fade
        y[ramp] *= 0.5 - 0.5 * np.cos(np.pi * t[ramp] / a.fade)
    with open(a.output, "w") as f:
        f.write(f"time,{a.name}\n")
        for ti, yi in zip(t, y):
            f.write(f"{ti:.9e},{yi:.9e}\n")
    print(f"wrote {a.output}: {n} samples, {a.kind}, rms {np.sqrt(np.mean(y * y)):.4g}")


if __name__ == "__main__":
    main()
