"""Trajectory #1 of the Robolink pFMB against its FMBs (thesis §4.5.4.2, Fig. 4.34–4.36): the
deck ``decks/robot/fmb/robot_trajectory1.dat`` (BDF1, Δt = 1 ms, from the static equilibrium)
run with the three artifact sets of ``tools/robot/static_map.py`` (pFMB; ROMs at the reference
parameters; ROMs with 40 modes per body), over the first ``--t-end`` seconds; with ``--sets``
also at the parameter sets 1 and 3 (every body's E × 0.6, ρ × 1.4 and E × 1.4, ρ × 0.6: the
pFMB with a PVAL against ROMs reduced at those values). Error of
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

from model import LINKS  # noqa: E402
from paraflex_tools.cards import card  # noqa: E402
from paraflex_tools.prom_decks import rom_deck_e_rho  # noqa: E402
from paraflex_tools.runner import find_binary, run_checked  # noqa: E402
from static_map import BODIES, deck_text  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
DECKS = REPO / "decks" / "robot" / "fmb"
PROVENANCE = "tools/robot/trajectory_compare.py"
FILES = ("robot_trajectory1.dat", "robot_bodies.inc", "robot_sensors.inc", "trajectory1.inc",
         "trajectory1.csv")
OUTPUTS = {"EEDEV": ("EE deviation (mm)", 1e3), "EEAZ": ("EE vertical acceleration (m/s²)", 1.0),
           "EPS2": ("L2r strain (µε)", 1e6), "EPS3": ("L3r strain (µε)", 1e6)}
VARIANTS = {"pfmb": "pFMB", "fmb": "FMB (ROMs at p)", "fmb40": "ROMs, 40 modes per body"}
# the parameter sets 1 and 3 of thesis §4.4.3 / §4.5.4 as factors on every body's (E, ρ)
SETS = {"set1": (0.6, 1.4), "set3": (1.4, 0.6)}


def pval(factors: tuple[float, float]) -> str:
    """The PVAL card setting every body's E and ρ to ``factors`` × its reference value."""
    pairs = []
    for _, name, artifact, *_ in LINKS:
        e, rho = BODIES[artifact.removesuffix(".h5")]
        pairs += [f"{name}.E", repr(e * factors[0]), f"{name}.RHO", repr(rho * factors[1])]
    return card("PVAL", 1, *pairs)


def build_roms_at(d: Path, factors: tuple[float, float], binary: Path) -> None:
    """The FMB's artifacts in ``d``: each body's ROM reduced at ``factors`` × (E, ρ)."""
    d.mkdir(parents=True, exist_ok=True)
    for name, (e, rho) in BODIES.items():
        deck = d / f"{name}_prom.dat"
        deck.write_text(rom_deck_e_rho(deck_text(name, "pfmb"), 1, e * factors[0],
                                       rho * factors[1]))
        run_checked(deck, d / f"{name}.h5", binary)


def run_window(d: Path, steps: int, binary: Path, pval_card: str = "",
               tag: str = "") -> tuple[dict, float]:
    """The sensors over the window in artifact directory ``d`` (with ``pval_card`` selected
    when given); the integration's wall time."""
    for f in FILES:
        shutil.copy(DECKS / f, d / f)
    deck = d / f"trajectory1_window{tag}.dat"
    text = (d / "robot_trajectory1.dat").read_text()
    text = text.replace("TSTEP,1,9000,1.e-3,1", f"TSTEP,1,{steps},1.e-3,1")
    if pval_card:
        text = text.replace("FMBSTART = STATIC\n", "FMBSTART = STATIC\nPVAL = 1\n")
        text = text.replace("BEGIN BULK\n", "BEGIN BULK\n" + pval_card)
    deck.write_text(text)
    out = d / f"trajectory1_window{tag}.h5"
    res = run_checked(deck, out, binary)
    seconds = float(re.search(r"multibody ([0-9.]+) s", res.stdout).group(1))
    with h5py.File(out, "r") as f:
        g = f["results/1/fmb"]
        out = {"time": g["time"][()]} | {k: g[f"sensors/{k}"][()] for k in OUTPUTS}
    return out, seconds


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--paraflex")
    ap.add_argument("--work", type=Path, default=Path("/tmp/robot_static_map"))
    ap.add_argument("--t-end", type=float, default=2.0)
    ap.add_argument("--sets", action="store_true",
                    help="also parameter sets 1 and 3: pFMB (PVAL) against ROMs reduced there")
    args = ap.parse_args()
    binary = find_binary(args.paraflex)
    steps = round(args.t_end / 1e-3)
    runs, wall = {}, {}
    for v in VARIANTS:
        runs[v], wall[v] = run_window(args.work / v, steps, binary)
    p = runs["pfmb"]

    def error(y: dict, ref: dict) -> dict:
        return {k: float(np.max(np.abs(y[k] - ref[k])) / np.max(np.abs(ref[k]))) for k in OUTPUTS}

    errors = {ref: error(p, runs[ref]) for ref in ("fmb", "fmb40")}
    if args.sets:
        for name, factors in SETS.items():
            build_roms_at(args.work / f"fmb_{name}", factors, binary)
            fmb, wall[f"fmb_{name}"] = run_window(args.work / f"fmb_{name}", steps, binary)
            pfmb, wall[f"pfmb_{name}"] = run_window(args.work / "pfmb", steps, binary,
                                                    pval(factors), f"_{name}")
            errors[f"fmb_{name}"] = error(pfmb, fmb)
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
