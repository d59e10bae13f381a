"""The Robolink AMANDA-EKF cases of thesis Table 9.2: runs the decks of decks/robot/estimate/
(the artifacts built beside decks/robot/fmb/robot_bodies.inc, docs/robot.md; the measurements of
tools/amanda/robot_measurements.py in reference/), and writes the error table over the last
20 % of each run, as Table 9.2: min / avg / max of 100 (p̂ − p) / p per parameter (p the true
value, or L2R.E(t) of the data in the degrading case), and for the input case the input's RMS
error over its RMS over the last 20 %, with the time per step the run reports (wall clock of the steps) and its CPU time per
step (the filter's whole phase, setup and start-of-run observability included, over the steps).

Writes reference/robot/amanda_table_9_2.csv and the figures docs/img/amanda_robot_<case>.png
(each parameter's estimate over the truth with its ±3σ band, both maneuvers; the input case
also the force over the last second).

    .venv/bin/python tools/amanda/robot_cases.py --binary target/release/paraflex
        [--cases e degrading input] [--trajectories 1 2] [--steps N]
"""

import argparse
import csv
import pathlib
import re
import tempfile

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from paraflex_tools.runner import run_checked  # noqa: E402

ROOT = pathlib.Path(__file__).resolve().parents[2]
DECKS = ROOT / "decks/robot/estimate"
TRUE_E = {"L2R.E": 201.99e9, "L3R.E": 194.37e9}
# thesis Table 9.2: (case, maneuver, parameter) -> (min, avg, max) in %
TABLE_9_2 = {
    ("e", 1, "L2R.E"): (-0.17, -0.04, 0.06), ("e", 1, "L3R.E"): (0.07, 0.16, 0.27),
    ("e", 2, "L2R.E"): (-0.18, -0.05, 0.04), ("e", 2, "L3R.E"): (0.07, 0.18, 0.29),
    ("degrading", 1, "L2R.E"): (0.11, 0.19, 0.28), ("degrading", 1, "L3R.E"): (-0.16, -0.04, 0.06),
    ("degrading", 2, "L2R.E"): (0.07, 0.17, 0.27), ("degrading", 2, "L3R.E"): (-0.03, 0.08, 0.18),
    ("input", 1, "L2R.E"): (-0.83, -0.10, 0.57), ("input", 1, "L3R.E"): (-1.32, -0.27, 0.88),
    ("input", 2, "L2R.E"): (-1.38, -0.66, 0.14), ("input", 2, "L3R.E"): (-2.04, -0.89, 0.26),
}


def measurements(case: str, trajectory: int) -> dict:
    path = ROOT / "reference" / f"amanda_robot_{case}_traj{trajectory}.csv"
    with open(path) as f:
        lines = [line for line in f if line.startswith("#")]
    names = lines[-1].lstrip("# ").strip().split(",")
    data = np.loadtxt(path, delimiter=",")
    return {n: data[:, i] for i, n in enumerate(names)}


def run_case(case: str, trajectory: int, binary: str, steps: int | None, work: pathlib.Path) -> dict:
    """The deck's run (its output and console log kept in `work`; an existing pair is read
    instead of running again)."""
    out, log = work / f"{case}_traj{trajectory}.h5", work / f"{case}_traj{trajectory}.log"
    if not (out.exists() and log.exists()):
        text = (DECKS / f"robot_estimate_{case}_traj{trajectory}.dat").read_text()
        if steps:
            text = text.replace("TSTEP,1,9000,", f"TSTEP,1,{steps},")
        path = DECKS / f"_run_{case}_traj{trajectory}.dat"
        path.write_text(text)
        try:
            log.write_text(run_checked(path, out, binary).stdout)
        finally:
            path.unlink()
    console = log.read_text()
    ms = re.search(r"([0-9.E+-]+) ms/step", console)
    # CPU seconds of the filter's phase (the whole run: setup, observability window, steps)
    cpu = re.search(r"subcase 1: AMANDA-EKF\s+[0-9.]+\s+([0-9.]+)", console)
    with h5py.File(out, "r") as f:
        g = f["results/1/estimate"]
        steps = len(g["time"])
        run = {"time": g["time"][()], "ms_per_step": float(ms.group(1)) if ms else float("nan"),
               "cpu_ms_per_step": 1e3 * float(cpu.group(1)) / steps if cpu else float("nan"),
               "params": {n: g[f"params/{n}"][()] for n in g["params"]},
               "sigma": {n: g[f"params_sigma/{n}"][()] for n in g["params_sigma"]},
               "inputs": {n: g[f"inputs/{n}"][()] for n in g["inputs"]} if "inputs" in g else {},
               "constraint": float(np.max(g["constraint_residual"][()]))}
    return run


def truth_of(name: str, data: dict, time: np.ndarray) -> np.ndarray:
    if name in data:
        return np.interp(time, data["time"], data[name])
    return np.full_like(time, TRUE_E[name])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--binary", required=True)
    parser.add_argument("--cases", nargs="+", default=["e", "degrading", "input"])
    parser.add_argument("--trajectories", nargs="+", type=int, default=[1, 2])
    parser.add_argument("--steps", type=int, default=None, help="cut the runs (default: the decks' 9000)")
    parser.add_argument("--runs", default=None,
                        help="keep the runs' outputs here and reuse those present (default: a temp dir)")
    parser.add_argument("-o", "--output", default=str(ROOT / "reference/robot/amanda_table_9_2.csv"))
    args = parser.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        work = pathlib.Path(args.runs or tmp)
        work.mkdir(parents=True, exist_ok=True)
        for case in args.cases:
            fig, axes = plt.subplots(len(args.trajectories), 3 if case == "input" else 2,
                                     figsize=(12, 3.2 * len(args.trajectories)), squeeze=False)
            for r, trajectory in enumerate(args.trajectories):
                run = run_case(case, trajectory, args.binary, args.steps, work)
                data = measurements(case, trajectory)
                t = run["time"]
                tail = int(np.floor(0.8 * len(t)))
                for c, (name, p) in enumerate(sorted(run["params"].items())):
                    truth = truth_of(name, data, t)
                    err = 100.0 * (p - truth) / truth
                    lo, avg, hi = err[tail:].min(), err[tail:].mean(), err[tail:].max()
                    thesis = TABLE_9_2.get((case, trajectory, name), (np.nan,) * 3)
                    rows.append([case, trajectory, name, len(t), f"{lo:.4f}", f"{avg:.4f}", f"{hi:.4f}",
                                 *thesis, "", f"{run['ms_per_step']:.1f}", f"{run['cpu_ms_per_step']:.1f}",
                                 f"{run['constraint']:.2e}"])
                    print(rows[-1])
                    ax = axes[r, c]
                    s = 3.0 * run["sigma"][name]
                    ax.fill_between(t, (p - s) / 1e9, (p + s) / 1e9, color="C0", alpha=0.25, lw=0)
                    ax.plot(t, p / 1e9, "C0", lw=1, label="estimate ±3σ")
                    ax.plot(t, truth / 1e9, "k--", lw=1, label="truth")
                    lim = truth.mean() / 1e9
                    ax.set_ylim(0.9 * lim, 1.3 * lim)
                    ax.set_title(f"{name}, maneuver {trajectory}", fontsize=9)
                    ax.set_xlabel("t (s)")
                    ax.set_ylabel("E (GPa)")
                    ax.legend(fontsize=7)
                for name, u in run["inputs"].items():
                    force = np.interp(t, data["time"], data["force"])
                    rms = np.sqrt(np.mean((u[tail:] - force[tail:]) ** 2)) / np.sqrt(np.mean(force[tail:] ** 2))
                    rows.append([case, trajectory, name, len(t), "", "", "", "", "", "",
                                 f"{rms:.4f}", f"{run['ms_per_step']:.1f}", f"{run['cpu_ms_per_step']:.1f}",
                                 f"{run['constraint']:.2e}"])
                    print(rows[-1])
                    ax = axes[r, 2]
                    last = t >= t[-1] - 1.0
                    ax.plot(t[last], force[last], "k--", lw=1, label="truth")
                    ax.plot(t[last], u[last], "C1", lw=1, label="estimate")
                    ax.set_title(f"EE input (N), maneuver {trajectory}, last second", fontsize=9)
                    ax.set_xlabel("t (s)")
                    ax.legend(fontsize=7)
            fig.tight_layout()
            fig.savefig(ROOT / "docs/img" / f"amanda_robot_{case}.png", dpi=110)
            plt.close(fig)
    with open(args.output, "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["# Robolink AMANDA-EKF, thesis Table 9.2 (tools/amanda/robot_cases.py): error in % over the "
                    "last 20 % of the run; input rows: RMS error / RMS of the input over the last 20 %"])
        w.writerow(["case", "maneuver", "unknown", "steps", "min", "avg", "max", "thesis_min", "thesis_avg",
                    "thesis_max", "input_rms_ratio", "ms_per_step", "cpu_ms_per_step", "max_constraint_residual"])
        w.writerows(rows)
    print(f"wrote {args.output}")


if __name__ == "__main__":
    main()
