#!/usr/bin/env python3
"""The flexible steel four-bar, paraflex against the independent peer Exudyn (docs/fourbar.md,
"Peer: Exudyn"): ``fourbar_exudyn.png`` overlays the drive torque, the deviation of the coupler
joint C from the rigid twin (eq. 4.10) and the coupler's strain gauge of paraflex's `SOL FMB`
with Exudyn's (reference/exudyn/fourbar_flexible.json, tools/exudyn/fourbar_flexible.py), the
rigid four-bar's torque for scale, and prints the eq. 4.11 differences.

paraflex runs decks/fourbar/fmb/fourbar_steel.dat as tests/fourbar.rs
(`flexible_four_bar_matches_exudyn`) does: the drive in closed form sampled every 10 µs,
generalized-α with ρ∞ = 0.9 at --dt (default 0.1 ms), over the reference's 0.2 s.

    .venv/bin/python tools/plot/fourbar_exudyn.py [--paraflex BIN] [--out docs/img] [--dt 1e-4]
"""
from __future__ import annotations

import argparse
import json
import math
import re
import tempfile
from pathlib import Path

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from paraflex_tools.runner import find_binary, run_checked  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
DECKS = ROOT / "decks/fourbar/fmb"
REFERENCE = ROOT / "reference/exudyn/fourbar_flexible.json"
LINKS = ["crank", "coupler", "output_crank"]


def closed_form_table(path: Path, t_end: float) -> None:
    """drive_table.py's θ(t) every 10 µs to t_end + 10 ms, at full precision (a table rounded
    to 7 digits puts noise of percent size into the drive's acceleration), with the knot times
    of tests/fourbar.rs (`closed_form_drive`): the steps fall on knots, and which segment's
    slope the drive takes there follows the knot times' last bit (0.06 % of the torque)."""
    span = round(t_end + 0.01, 9)
    n = round(span / 1e-5)
    rows = []
    for k in range(n + 1):
        t = span * k / n
        rows.append(f"{t!r},{math.radians(20.0) * (1 - abs(2 * t - 1)) * math.sin(20 * math.pi * t)!r}")
    path.write_text("time,angle\n" + "\n".join(rows) + "\n")


def run_paraflex(binary: Path, work: Path, dt: float, t_end: float) -> tuple[dict, float]:
    """The steel four-bar's sensors, one sample per millisecond, and the run's multibody time."""
    for link in LINKS:
        text = (DECKS / f"{link}_prom.dat").read_text().replace("'../../../meshes/", f"'{ROOT / 'meshes'}/")
        (work / f"{link}_prom.dat").write_text(text)
        run_checked(work / f"{link}_prom.dat", work / f"{link}.h5", binary)
    closed_form_table(work / "fine.csv", t_end)
    steps, every = round(t_end / dt), round(1e-3 / dt)
    text = (DECKS / "fourbar_steel.dat").read_text()
    for old, new in [("TINTEG,1,BDF1", "TINTEG,1,GALPHA,0.9"), ("'drive.csv'", "'fine.csv'"),
                     ("TSTEP,1,1000,1.e-3,1", f"TSTEP,1,{steps},{dt!r},{every}")]:
        assert old in text, old
        text = text.replace(old, new)
    (work / "fourbar.dat").write_text(text)
    run = run_checked(work / "fourbar.dat", work / "fourbar.h5", binary)
    with h5py.File(work / "fourbar.h5", "r") as f:
        g = f["results/1/fmb"]
        sensors = {name: g[f"sensors/{name}"][()] for name in ("TORQUE", "CDEV", "CEPS", "CX", "CY")}
        time = g["time"][()]
    found = re.search(r"multibody ([0-9.]+) s", run.stdout)
    multibody = float(found.group(1)) if found else float("nan")
    return {"time": time, "torque": sensors["TORQUE"], "deviation": sensors["CDEV"],
            "strain_c": sensors["CEPS"]}, multibody


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--paraflex", default=None, help="paraflex binary (default: the release build)")
    ap.add_argument("--out", type=Path, default=ROOT / "docs/img")
    ap.add_argument("--dt", type=float, default=1e-4)
    args = ap.parse_args()
    ref = json.loads(REFERENCE.read_text())
    exudyn = {k: np.asarray(ref[k]) for k in ("time", "torque", "deviation", "strain_c", "rigid_torque")}
    with tempfile.TemporaryDirectory() as work:
        ours, multibody = run_paraflex(find_binary(args.paraflex), Path(work), args.dt, exudyn["time"][-1])
    panels = [("torque", "drive torque [N m]", 1.0), ("deviation", "deviation of C [µm]", 1e6),
              ("strain_c", "strain of the coupler gauge [µε]", 1e6)]
    fig, axes = plt.subplots(len(panels), 1, figsize=(8, 8), sharex=True)
    for ax, (key, label, scale) in zip(axes, panels):
        difference = np.abs(ours[key] - exudyn[key]).max() / np.abs(exudyn[key]).max()
        print(f"{key}: eq. 4.11 difference {difference:.2e}")
        if key == "torque":
            ax.plot(exudyn["time"], exudyn["rigid_torque"], color="0.7", lw=1, label="rigid four-bar (Exudyn)")
        ax.plot(exudyn["time"], scale * exudyn[key], lw=2.2, color="tab:orange",
                label=f"Exudyn {ref['provenance']['code'].split()[1]}")
        ax.plot(ours["time"], scale * ours[key], lw=1, color="tab:blue", label="paraflex SOL FMB")
        ax.set_ylabel(label)
        ax.set_title(f"eq. 4.11 difference {100 * difference:.2f} %", fontsize=9, loc="right")
        ax.grid(alpha=0.3)
    axes[0].legend(fontsize=8, loc="lower left")
    axes[-1].set_xlabel("time [s]")
    fig.suptitle(f"Flexible steel four-bar: paraflex (generalized-α, Δt = {args.dt * 1e3:g} ms) "
                 f"vs Exudyn (Δt = 25 µs)", fontsize=10)
    fig.tight_layout()
    args.out.mkdir(parents=True, exist_ok=True)
    fig.savefig(args.out / "fourbar_exudyn.png", dpi=110)
    print(f"paraflex multibody step: {multibody:.3f} s; Exudyn: {ref['provenance']['wall_time_s']} s")
    print(args.out / "fourbar_exudyn.png")


if __name__ == "__main__":
    main()
