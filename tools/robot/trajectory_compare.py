"""Trajectory #1 of the Robolink pFMB against its FMBs (thesis §4.5.4.2, Fig. 4.34–4.36): the
deck ``decks/robot/fmb/robot_trajectory1.dat`` (BDF1, Δt = 1 ms, from the static equilibrium)
run with the three artifact sets of ``tools/robot/static_map.py`` (pFMB; ROMs at the reference
parameters; ROMs with 40 modes per body), over the first ``--t-end`` seconds. Error of
eq. 4.11 per output, max_t |y_pFMB(t) − y_ref(t)| / max_t |y_ref(t)|, for the EE deviation and
vertical acceleration and the L2r / L3r gauges; the histories as
``docs/img/robot_trajectory1.png``; the numbers and wall times in
``reference/robot/trajectory1_compare.json``.

Run (after static_map.py has built the artifacts in WORK):
``.venv/bin/python tools/robot/trajectory_compare.py --paraflex target/release/paraflex --t-end 2``
"""
from __future__ import annotations

import argparse
import json
import re
import shutil
from pathlib import Path

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from paraflex_tools.runner import find_binary, run_checked  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
DECKS = REPO / "decks" / "robot" / "fmb"
PROVENANCE = "tools/robot/trajectory_compare.py"
FILES = ("robot_trajectory1.dat", "robot_bodies.inc", "robot_sensors.inc", "trajectory1.inc",
         "trajectory1.csv")
OUTPUTS = {"EEDEV": ("EE deviation (mm)", 1e3), "EEAZ": ("EE vertical acceleration (m/s²)", 1.0),
           "EPS2": ("L2r strain (µε)", 1e6), "EPS3": ("L3r strain (µε)", 1e6)}
VARIANTS = {"pfmb": "pFMB", "fmb": "FMB (ROMs at p)", "fmb40": "ROMs, 40 modes per body"}


def run_window(d: Path, steps: int, binary: Path) -> tuple[dict, float]:
    """The sensors over the window in artifact directory ``d``; the integration's wall time."""
    for f in FILES:
        shutil.copy(DECKS / f, d / f)
    deck = d / "trajectory1_window.dat"
    text = (d / "robot_trajectory1.dat").read_text()
    deck.write_text(text.replace("TSTEP,1,9000,1.e-3,1", f"TSTEP,1,{steps},1.e-3,1"))
    res = run_checked(deck, d / "trajectory1_window.h5", binary)
    seconds = float(re.search(r"multibody ([0-9.]+) s", res.stdout).group(1))
    with h5py.File(d / "trajectory1_window.h5", "r") as f:
        g = f["results/1/fmb"]
        out = {"time": g["time"][()]} | {k: g[f"sensors/{k}"][()] for k in OUTPUTS}
    return out, seconds


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--paraflex")
    ap.add_argument("--work", type=Path, default=Path("/tmp/robot_static_map"))
    ap.add_argument("--t-end", type=float, default=2.0)
    args = ap.parse_args()
    binary = find_binary(args.paraflex)
    steps = round(args.t_end / 1e-3)
    runs, wall = {}, {}
    for v in VARIANTS:
        runs[v], wall[v] = run_window(args.work / v, steps, binary)
    p = runs["pfmb"]
    errors = {ref: {k: float(np.max(np.abs(p[k] - runs[ref][k])) / np.max(np.abs(runs[ref][k])))
                    for k in OUTPUTS} for ref in ("fmb", "fmb40")}
    fig, axs = plt.subplots(len(OUTPUTS), 1, figsize=(9, 10), sharex=True)
    for ax, (k, (label, scale)) in zip(axs, OUTPUTS.items()):
        for v, style in (("pfmb", "-"), ("fmb40", "--")):
            ax.plot(runs[v]["time"], runs[v][k] * scale, style, label=VARIANTS[v], lw=1)
        ax.set_ylabel(label)
    axs[0].legend()
    axs[-1].set_xlabel("time (s)")
    fig.suptitle(f"Robolink trajectory #1, first {args.t_end:g} s: pFMB and 40-mode ROMs")
    fig.tight_layout()
    fig.savefig(REPO / "docs" / "img" / "robot_trajectory1.png", dpi=100)
    doc = {"provenance": PROVENANCE, "binary": str(binary), "t_end": args.t_end, "dt": 1e-3,
           "integrator": "BDF1", "eq_4_11_error": errors, "integration_wall_s": wall}
    (REPO / "reference" / "robot" / "trajectory1_compare.json").write_text(
        json.dumps(doc, indent=1) + "\n")
    print(json.dumps(doc, indent=1))


if __name__ == "__main__":
    main()
