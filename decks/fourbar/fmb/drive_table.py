#!/usr/bin/env python3
"""Writes drive.csv, the input-crank drive of the four-bar FMB decks (thesis §4.4.2, Fig. 4.4):
a 10 Hz sine whose amplitude ramps linearly 0 → 20° → 0 over 1 s,

    θ(t) = 20° · (1 − |2t − 1|) · sin(2π · 10 Hz · t)   [rad], 0 ≤ t ≤ 1 s,

sampled every 0.25 ms (JDRIVE interpolates linearly, so steps of 1 ms and 0.25 ms both see
the same motion at their step ends)."""
import math
from pathlib import Path

DT, T_END, F, AMPLITUDE = 2.5e-4, 1.0, 10.0, math.radians(20.0)


def angle(t: float) -> float:
    return AMPLITUDE * (1.0 - abs(2.0 * t - 1.0)) * math.sin(2.0 * math.pi * F * t)


def main() -> None:
    n = round(T_END / DT)
    rows = ["time,angle"] + [f"{k * DT:.9e},{angle(k * DT):.12e}" for k in range(n + 1)]
    (Path(__file__).resolve().parent / "drive.csv").write_text("\n".join(rows) + "\n")


if __name__ == "__main__":
    main()
