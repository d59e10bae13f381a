#!/usr/bin/env python3
"""MOOPT GRAD against NSGA-II on the four-bar design study (decks/fourbar/fmb/optimize_composite.dat,
docs/optimize.md): hypervolume against evaluations at equal budgets, and the forward
sensitivities' accuracy and cost over a longer window.

    .venv/bin/python tools/bench/optimize_bench.py [--budgets 24 48] [--steps 300] [--paraflex target/release/paraflex] [--keep DIR]

Builds the three links' pROM artifacts in a work directory, then

1. runs the study deck with `MOOPT NSGA2` (population 8, seed 1) and with `MOOPT GRAD` (POP 3
   weights per crank density) at each budget, and prints the hypervolume of the feasible
   designs evaluated so far after every evaluation (both studies against one reference point:
   the worst feasible value of each objective over both runs plus a tenth of its range, so the
   numbers compare);
2. runs `paraflex evaluate --gradient` on a deck whose five link parameters are all continuous
   variables, over --steps BDF1 steps, against central differences (step 1e-4 of each value):
   the largest difference per response in units of the response's change over the variable
   ranges, and the time of the gradient run against a plain evaluation.

Prints, asserts nothing: a benchmark, not a test.
"""
from __future__ import annotations

import argparse
import json
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

import h5py
import numpy as np

from paraflex_tools.fourbar_work import DECKS, prepare_links
from paraflex_tools.runner import default_binary, run_checked

LINKS = {"crank_prom.dat": "crank.h5", "coupler_composite_prom.dat": "coupler_composite.h5",
         "output_crank_prom.dat": "output_crank.h5"}
MOOPT = "MOOPT,1,NSGA2,24,8,1,2"
EVERY_PARAMETER = """DESVAR,1,THETA,45.,0.,90.
DESVAR,2,RHOI,7990.,6000.,10000.
DESVAR,3,RHOO,7990.,6000.,10000.
DESVAR,4,EI,2.e11,1.5e11,2.5e11
DESVAR,5,EO,2.e11,1.5e11,2.5e11
DVMAP,1,1,C.THETA
DVMAP,2,2,IC.RHO
DVMAP,3,3,OC.RHO
DVMAP,4,4,IC.E
DVMAP,5,5,OC.E
DOBJ,1,DEV,MIN,CDEV,MEAN
DOBJ,2,ENERGY,MIN,WORK,FINAL
DCONSTR,3,TORQUE,TORQUE,MAX,,0.1
DCONSTR,4,STRAIN,CEPS,RMS,,1.
DCONSTR,5,MASS,MASS,,,10.
"""
DESIGN = [30.0, 7000.0, 8000.0, 1.8e11, 2.2e11]
RANGES = [90.0, 4000.0, 4000.0, 1e11, 1e11]
RESPONSES = ["DEV mean", "energy", "peak torque", "strain RMS", "mass"]


def hypervolume_2d(points: np.ndarray, reference: np.ndarray) -> float:
    """Area dominated by `points` (minimized) below `reference`: the 2-D sweep."""
    inside = points[np.all(points < reference, axis=1)]
    if len(inside) == 0:
        return 0.0
    inside = inside[np.argsort(inside[:, 0])]
    area, best = 0.0, reference[1]
    for x, y in inside:
        if y < best:
            area += (reference[0] - x) * (best - y)
            best = y
    return area


def study(work: Path, deck: str, name: str, exe: Path) -> tuple[np.ndarray, np.ndarray, float]:
    """Runs a study deck: its objectives (n × 2), feasibility and wall time."""
    (work / f"{name}.dat").write_text(deck)
    start = time.perf_counter()
    run_checked(work / f"{name}.dat", work / f"{name}.h5", exe)
    wall = time.perf_counter() - start
    with h5py.File(work / f"{name}.h5") as f:
        g = f["results/1/optimize"]
        responses = g["responses"][()].reshape(-1, 3)
        feasible = g["feasible"][()].astype(bool)
    return responses[:, :2], feasible, wall


def evaluate(work: Path, deck: Path, designs: list[list[float]], exe: Path, *extra: str) -> list[dict]:
    """`paraflex evaluate`'s JSON lines."""
    path = work / "designs.json"
    path.write_text(json.dumps(designs))
    out = subprocess.run([str(exe), "evaluate", str(deck), "--designs", str(path), *extra],
                         capture_output=True, text=True, check=True).stdout
    return [json.loads(line) for line in out.splitlines()]


def sensitivities(work: Path, exe: Path, steps: int) -> None:
    text = (DECKS / "optimize_composite.dat").read_text().replace("TSTEP,1,100,", f"TSTEP,1,{steps},")
    start, end = text.index("\nDESVAR,1") + 1, text.index("\nMOOPT,") + 1
    deck = work / "every_parameter.dat"
    deck.write_text(text[:start] + EVERY_PARAMETER + text[end:])
    t0 = time.perf_counter()
    line = evaluate(work, deck, [DESIGN], exe, "--gradient")[0]
    t_gradient = time.perf_counter() - t0
    t0 = time.perf_counter()
    evaluate(work, deck, [DESIGN], exe)
    t_plain = time.perf_counter() - t0
    gradient = np.array(line["gradient"], dtype=float)
    designs = []
    for i, x in enumerate(DESIGN):
        for sign in (1, -1):
            d = list(DESIGN)
            d[i] = x + sign * 1e-4 * x
            designs.append(d)
    r = np.array([l["responses"] for l in evaluate(work, deck, designs, exe)], dtype=float)
    print(f"\nforward sensitivities, {steps} BDF1 steps, 5 parameters: gradient run {t_gradient:.2f} s, "
          f"plain evaluation {t_plain:.2f} s (each a paraflex process, the artifacts read included); "
          f"{line['sensitivity_iterations'] / (5 * steps):.2f} sensitivity iterations per step and parameter")
    print(f"{'response':>12}{'|sens − FD| / scale':>22}")
    for k, name in enumerate(RESPONSES):
        fd = np.array([(r[2 * i, k] - r[2 * i + 1, k]) / (2e-4 * DESIGN[i]) for i in range(5)])
        scale = np.max(np.abs(fd * RANGES))
        error = np.max(np.abs((gradient[k] - fd) * RANGES))
        print(f"{name:>12}{error / scale if scale else error:>22.2e}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--budgets", type=int, nargs="+", default=[24, 48])
    ap.add_argument("--steps", type=int, default=300)
    ap.add_argument("--paraflex", type=Path, default=default_binary())
    ap.add_argument("--keep", type=Path, help="work directory to keep (default: a temp directory)")
    a = ap.parse_args()
    work = a.keep or Path(tempfile.mkdtemp(prefix="optimize_bench_"))
    work.mkdir(parents=True, exist_ok=True)
    prepare_links(work, LINKS, a.paraflex)
    base = (DECKS / "optimize_composite.dat").read_text()
    if MOOPT not in base:
        raise RuntimeError(f"{MOOPT} not in optimize_composite.dat")
    for budget in a.budgets:
        runs = {
            "NSGA2": study(work, base.replace(MOOPT, f"MOOPT,1,NSGA2,{budget},8,1,2"), f"nsga2_{budget}", a.paraflex),
            "GRAD": study(work, base.replace(MOOPT, f"MOOPT,1,GRAD,{budget},3,1,1"), f"grad_{budget}", a.paraflex),
        }
        feasible = np.vstack([f[ok] for f, ok, _ in runs.values()])
        worst, best = feasible.max(axis=0), feasible.min(axis=0)
        reference = worst + 0.1 * (worst - best)
        print(f"\nbudget {budget}: hypervolume of the feasible designs after each evaluation "
              f"(reference {reference[0]:.4e} m, {reference[1]:.4e} J)")
        history = {}
        for label, (f, ok, wall) in runs.items():
            history[label] = [hypervolume_2d(f[: n + 1][ok[: n + 1]], reference) for n in range(len(f))]
            print(f"  {label}: {len(f)} evaluations, {wall:.1f} s wall, final hypervolume {history[label][-1]:.4e}")
        print(f"{'evaluations':>12}" + "".join(f"{label:>14}" for label in history))
        for n in sorted({max(1, round(budget * q / 8)) for q in range(1, 9)}):
            row = [h[min(n, len(h)) - 1] for h in history.values()]
            print(f"{n:>12}" + "".join(f"{v:>14.4e}" for v in row))
    sensitivities(work, a.paraflex, a.steps)
    print(f"work directory: {work}" if a.keep else "")
    if not a.keep:
        shutil.rmtree(work)


if __name__ == "__main__":
    main()
