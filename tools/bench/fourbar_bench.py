#!/usr/bin/env python3
"""Speed against error of the flexible four-bar of thesis §4.4 (decks/fourbar/fmb/fourbar_steel.dat,
docs/fourbar.md): 1 s of the drive with BDF1 at Δt = 1 ms, timed, and its error against
Δt = 0.25 ms; with --integrators, each GGL integrator (BDF1, BDF2, generalized-α with
ρ∞ = 0.9) at Δt = 2, 1 and 0.5 ms against generalized-α at 0.125 ms.

    .venv/bin/python tools/bench/fourbar_bench.py [--repeat 3] [--integrators] [--paraflex target/release/paraflex] [--keep DIR]

Builds the three links' pROM artifacts beside the deck in a work directory, runs the deck at
1 ms (1000 steps) and at 0.25 ms (4000 steps, output every 4th: the same output times).
Time: wall time of the run's "multibody" step as printed by paraflex (assembly, the time loop,
the sensors and their output) and CPU time of the whole run (its child-process rusage,
reading the artifacts included), each the best of --repeat runs (the median CPU time too, and
that of the deck without its DEV sensor, whose rigid twin is a second integration); Newton iterations per step from the
output's newton_iterations. On a machine shared with other jobs the wall time can be 2–3 × the
CPU time; compare binaries by the CPU time of a run of the kept work directory's coarse.dat
(`perf stat -e task-clock`, docs/fourbar.md "Speed"). Error: eq. 4.11 of the thesis,
max_t ‖y(t) − y_ref(t)‖ / max_t ‖y_ref(t)‖, on the acceleration (AX, AY) of the coupler joint C
and on the drive torque, over the output times the two runs share.
"""
from __future__ import annotations

import argparse
import re
import resource
import shutil
import tempfile
from pathlib import Path

import h5py
import numpy as np

from paraflex_tools.fourbar_work import DECKS, prepare_links
from paraflex_tools.runner import default_binary, run_checked

LINKS = {"crank_prom.dat": "crank.h5", "coupler_prom.dat": "coupler.h5", "output_crank_prom.dat": "output_crank.h5"}
COARSE_STEP = "TSTEP,1,1000,1.e-3,1"
FINE = (COARSE_STEP, "TSTEP,1,4000,2.5e-4,4")
INTEGRATOR = "TINTEG,1,BDF1"
SCHEMES = {"BDF1": "TINTEG,1,BDF1", "BDF2": "TINTEG,1,BDF2", "gen-α 0.9": "TINTEG,1,GALPHA,0.9"}
STEPS_MS = (2.0, 1.0, 0.5)
REFERENCE_MS = 0.125


def histories(path: Path) -> dict[str, np.ndarray]:
    with h5py.File(path, "r") as f:
        g = f["results/1/fmb"]
        return {
            "time": g["time"][()],
            "accel": np.column_stack([g["sensors/AX"][()], g["sensors/AY"][()]]),
            "torque": g["sensors/TORQUE"][()][:, None],
            "iterations": g["newton_iterations"][()],
        }


def error_4_11(y: np.ndarray, ref: np.ndarray) -> float:
    """max_t ‖y(t) − y_ref(t)‖ / max_t ‖y_ref(t)‖ (thesis eq. 4.11)."""
    return float(np.linalg.norm(y - ref, axis=1).max() / np.linalg.norm(ref, axis=1).max())


def errors(y: dict[str, np.ndarray], ref: dict[str, np.ndarray]) -> tuple[float, float]:
    """Eq. 4.11 errors of the acceleration of C and of the drive torque at the shared times."""
    common, iy, ir = np.intersect1d(np.round(y["time"], 9), np.round(ref["time"], 9), return_indices=True)
    if len(common) < 2:
        raise RuntimeError("the runs share no output times")
    return (error_4_11(y["accel"][iy], ref["accel"][ir]), error_4_11(y["torque"][iy], ref["torque"][ir]))


def without_twin(deck: str) -> str:
    """The deck without its DEV sensor (the one output that makes paraflex integrate the rigid
    twin, eq. 4.10, beside the flexible links)."""
    kept = [line for line in deck.splitlines() if not (line.startswith("MSENSOR") and ",DEV," in line)]
    if len(kept) == len(deck.splitlines()):
        raise RuntimeError("no DEV sensor in fourbar_steel.dat")
    return "\n".join(kept) + "\n"


def variant(deck: str, scheme: str, dt_ms: float, out_every_ms: float) -> str:
    """The deck with integrator `scheme` (a TINTEG line) and step Δt over 1 s, output every
    `out_every_ms`."""
    steps = round(1000.0 / dt_ms)
    every = max(1, round(out_every_ms / dt_ms))
    return deck.replace(COARSE_STEP, f"TSTEP,1,{steps},{dt_ms * 1e-3:.6e},{every}").replace(INTEGRATOR, scheme)


def integrator_table(work: Path, deck: str, exe: Path, repeat: int) -> None:
    """Prints Δt, steps, wall, Newton iterations per step and eq. 4.11 errors for each scheme."""
    (work / "reference.dat").write_text(variant(deck, SCHEMES["gen-α 0.9"], REFERENCE_MS, 1.0))
    run_checked(work / "reference.dat", work / "reference.h5", exe)
    ref = histories(work / "reference.h5")
    print(f"reference: generalized-α ρ∞ = 0.9 at Δt = {REFERENCE_MS} ms")
    print("| scheme | Δt (ms) | steps | wall (ms) | CPU (ms) | Newton it./step | accel. error | torque error |")
    print("|---|---|---|---|---|---|---|---|")
    for name, scheme in SCHEMES.items():
        for dt in STEPS_MS:
            deck_path, out = work / "variant.dat", work / "variant.h5"
            deck_path.write_text(variant(deck, scheme, dt, dt))
            wall, cpu = (min(t) for t in zip(*(timed_run(deck_path, out, exe) for _ in range(repeat))))
            y = histories(out)
            accel, torque = errors(y, ref)
            steps = round(1000.0 / dt)
            print(f"| {name} | {dt:g} | {steps} | {1e3 * wall:.0f} | {1e3 * cpu:.0f} | {y['iterations'][1:].mean():.2f} "
                  f"| {accel:.2e} | {torque:.2e} |")


def children_cpu() -> float:
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def timed_run(deck: Path, out: Path, exe: Path) -> tuple[float, float]:
    """Wall time of the run's multibody step and CPU time of the whole run (s)."""
    before = children_cpu()
    r = run_checked(deck, out, exe)
    cpu = children_cpu() - before
    m = re.search(r"multibody ([0-9.]+) s", r.stdout)
    if not m:
        raise RuntimeError(f"no multibody timing in:\n{r.stdout}")
    return float(m.group(1)), cpu


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--integrators", action="store_true",
                    help="also the table of each integrator at several steps")
    ap.add_argument("--paraflex", type=Path, default=default_binary())
    ap.add_argument("--keep", type=Path, help="work directory to keep (default: a temp directory)")
    a = ap.parse_args()
    work = a.keep or Path(tempfile.mkdtemp(prefix="fourbar_bench_"))
    work.mkdir(parents=True, exist_ok=True)
    prepare_links(work, LINKS, a.paraflex)
    coarse = (DECKS / "fourbar_steel.dat").read_text()
    for line in (COARSE_STEP, INTEGRATOR):
        if line not in coarse:
            raise RuntimeError(f"{line} not in fourbar_steel.dat")
    (work / "coarse.dat").write_text(coarse)
    (work / "fine.dat").write_text(coarse.replace(*FINE))
    runs = [timed_run(work / "coarse.dat", work / "coarse.h5", a.paraflex) for _ in range(a.repeat)]
    wall, cpu = (min(t) for t in zip(*runs))
    median_cpu = float(np.median([r[1] for r in runs]))
    # the same deck without its DEV sensor: no rigid twin to integrate beside the links
    (work / "no_twin.dat").write_text(without_twin(coarse))
    no_twin = [timed_run(work / "no_twin.dat", work / "no_twin.h5", a.paraflex)[1] for _ in range(a.repeat)]
    fine_wall, fine_cpu = timed_run(work / "fine.dat", work / "fine.h5", a.paraflex)
    y, ref = histories(work / "coarse.h5"), histories(work / "fine.h5")
    if not np.allclose(y["time"], ref["time"]):
        raise RuntimeError("output times differ")
    print(f"{'dt [s]':>8}{'steps':>7}{'wall [ms]':>11}{'CPU [ms]':>10}{'accel error':>13}{'torque error':>14}")
    print(f"{1e-3:>8.2e}{1000:>7}{1e3 * wall:>11.1f}{1e3 * cpu:>10.1f}{error_4_11(y['accel'], ref['accel']):>13.2e}"
          f"{error_4_11(y['torque'], ref['torque']):>14.2e}")
    print(f"{2.5e-4:>8.2e}{4000:>7}{1e3 * fine_wall:>11.1f}{1e3 * fine_cpu:>10.1f}{'(reference)':>13}{'':>14}")
    print(f"Newton iterations per step at 1 ms: {y['iterations'][1:].mean():.2f}")
    print(f"CPU at 1 ms, median of {a.repeat}: {1e3 * median_cpu:.1f} ms; without the DEV sensor (no rigid twin): "
          f"{1e3 * float(np.median(no_twin)):.1f} ms")
    if a.integrators:
        integrator_table(work, coarse, a.paraflex, a.repeat)
    print(f"work directory: {work}" if a.keep else "")
    if not a.keep:
        shutil.rmtree(work)


if __name__ == "__main__":
    main()
