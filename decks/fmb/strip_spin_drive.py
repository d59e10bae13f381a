#!/usr/bin/env python3
"""Writes strip_spin_drive.csv, the drive of strip_spin.dat: the strip's root joint turned about
z with a rate that ramps smoothly from 0 to W0 over T (angular acceleration
W0/T·(1 − cos 2πt/T): zero at both ends of the ramp) and stays at W0 after,

    θ(t) = W0·(t²/(2T) + T·(cos(2πt/T) − 1)/(4π²))   for t ≤ T,
    θ(t) = θ(T) + W0·(t − T)                          for t > T,

sampled every 1 ms over 0.7 s (beyond the deck's 0.6 s; at its steps the drive sees the
closed form)."""
import math
from pathlib import Path

W0, T, DT, T_END = 50.0, 0.3, 1e-3, 0.7


def angle(t: float) -> float:
    if t <= T:
        return W0 * (t * t / (2 * T) + T * (math.cos(2 * math.pi * t / T) - 1) / (4 * math.pi**2))
    return angle(T) + W0 * (t - T)


def main() -> None:
    n = round(T_END / DT)
    rows = ["time,angle"] + [f"{k * DT:.9e},{angle(k * DT):.12e}" for k in range(n + 1)]
    (Path(__file__).resolve().parent / "strip_spin_drive.csv").write_text("\n".join(rows) + "\n")


if __name__ == "__main__":
    main()
