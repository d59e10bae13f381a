"""Andrews' squeezing mechanism (decks/fmb/andrews.dat) against the test set's reference
solution at t = 0.03 s (reference/andrews/): a Δt convergence study of BDF1, BDF2 and
generalized-α (observed order from the slopes), and error-controlled steps (TSTEPVAR) at a
range of tolerances beside the fixed steps that reach the same error.

For each run it prints Δt (or RTOL), the steps, the error (the largest of the seven angles'
differences from the reference, modulo 2π, rad) and the wall time of `paraflex run`.

    .venv/bin/python tools/bench/andrews_bench.py [--paraflex BIN] [--quick]
"""
import argparse
import json
import math
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import h5py
import numpy as np

ROOT = Path(__file__).resolve().parents[2]
DECK = ROOT / "decks" / "fmb" / "andrews.dat"
REFERENCE = ROOT / "reference" / "andrews" / "solution_t0.03.json"
END = 0.03
ORDER = ["beta", "Theta", "gamma", "Phi", "delta", "Omega", "epsilon"]

# the deck's fixed points and link dimensions (andrews.f), to recover the angles
XA, YA, XB, YB = -0.06934, -0.00227, -0.03635, 0.03273
RR, D, ZT, U = 7e-3, 28e-3, 4e-2, 4e-2


def reference_points(a):
    """x, y of F, E, H and G from the reference angles (m)."""
    F = np.array([RR * math.cos(a["beta"]), RR * math.sin(a["beta"])])
    bt = a["beta"] + a["Theta"]
    E = F - D * np.array([math.cos(bt), math.sin(bt)])
    H = np.array([XA, YA]) + ZT * np.array([math.cos(a["delta"]), math.sin(a["delta"])])
    G = np.array([XA, YA]) + U * np.array([math.sin(a["epsilon"]), -math.cos(a["epsilon"])])
    return {"F": F, "E": E, "H": H, "G": G}


def position_error(f, a):
    """The largest difference of the x, y of F, E, H, G from the reference's (m)."""
    g = f["results/1/fmb/sensors"]
    ref = reference_points(a)
    return max(
        abs(g[k + c][-1] - ref[k][i]) for k in "FEHG" for i, c in enumerate("XY")
    )


def angles(f):
    """The test set's seven angles from the global x, y of F, E, H and G (rad, modulo 2π)."""
    g = f["results/1/fmb/sensors"]
    p = {k: np.array([g[k + "X"][-1], g[k + "Y"][-1]]) for k in "FEHG"}
    F, E, H, G = p["F"], p["E"], p["H"], p["G"]
    beta = math.atan2(F[1], F[0])
    bt = math.atan2(*(F - E)[::-1])
    gamma = math.atan2(E[0] - XB, -(E[1] - YB))
    delta = math.atan2(H[1] - YA, H[0] - XA)
    pd = math.atan2((E - H)[0], -(E - H)[1])
    eps = math.atan2(G[0] - XA, -(G[1] - YA))
    oe = math.atan2(*(E - G)[::-1])
    return [beta, bt - beta, gamma, pd - delta, delta, oe - eps, eps]


def error(values, reference):
    return max(
        abs(math.remainder(v - reference[k], 2 * math.pi)) for v, k in zip(values, ORDER)
    )


def binary(given):
    if given:
        return given
    if os.environ.get("PARAFLEX"):
        return os.environ["PARAFLEX"]
    target = Path(os.environ.get("CARGO_TARGET_DIR", ROOT / "target"))
    return str(target / "release" / "paraflex")


def run(exe, work, method, dt, control=None):
    """One run of the deck with TINTEG `method`, Δt (first step with control) and optional
    TSTEPVAR fields; returns (steps, rejected, error, wall)."""
    steps = round(END / dt)
    text = DECK.read_text()
    text = text.replace("TSTEP,1,3000,1.e-5,3000", f"TSTEP,1,{steps},{dt!r},{steps}")
    text = text.replace("TINTEG,1,BDF2", f"TINTEG,1,{method}")
    if control:
        text = text.replace("TINTEG,", f"TSTEPVAR,1,{control}\nTINTEG,", 1)
    deck = Path(work) / "andrews.dat"
    deck.write_text(text)
    out = Path(work) / "andrews.h5"
    start = time.perf_counter()
    subprocess.run([exe, "run", str(deck), "-o", str(out)], check=True, capture_output=True)
    wall = time.perf_counter() - start
    reference = json.loads(REFERENCE.read_text())["angles"]
    with h5py.File(out) as f:
        g = f["results/1/fmb"]
        taken = int(g.attrs.get("steps", steps))
        rejected = int(g.attrs.get("rejected_steps", 0))
        return (
            taken,
            rejected,
            error(angles(f), reference),
            position_error(f, reference),
            wall,
        )


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--paraflex")
    ap.add_argument("--quick", action="store_true", help="fewer step sizes and tolerances")
    args = ap.parse_args()
    exe = binary(args.paraflex)
    methods = ["BDF1", "BDF2", "GALPHA"]
    dts = [1e-4 / 2**k for k in range(2, 5 if args.quick else 7)]
    with tempfile.TemporaryDirectory() as work:
        print("fixed steps: Δt, steps, angle error (rad), observed order, position error (m), wall (s)")
        for m in methods:
            print(f"{m}:")
            last = None
            for dt in dts:
                taken, _, err, perr, wall = run(exe, work, m, dt)
                order = "" if last is None else f"{math.log2(last / err):6.2f}"
                print(f"  {dt:9.3e} {taken:7d} {err:10.3e} {order:>6} {perr:10.3e} {wall:8.3f}")
                last = err
        # BDF1 needs ~1/tol steps: its tightest tolerances are left out
        tolerances = {
            "BDF1": [1e-3] if args.quick else [1e-3, 1e-4],
            "BDF2": [1e-4, 1e-5, 1e-6] if args.quick else [1e-3, 1e-4, 1e-5, 1e-6, 1e-7],
        }
        tolerances["GALPHA"] = tolerances["BDF2"]
        print(
            "error-controlled steps (TSTEPVAR, ATOL = tol in m, RTOL = 0): tol, steps, rejected,"
            " angle error (rad), position error (m), wall (s)"
        )
        for m in methods:
            print(f"{m}:")
            for tol in tolerances[m]:
                try:
                    taken, rejected, err, perr, wall = run(exe, work, m, 1e-5, f"0.,{tol!r}")
                except subprocess.CalledProcessError as e:
                    print(f"  {tol:9.1e} failed: {e.stderr.decode().strip()[-200:]}")
                    continue
                print(f"  {tol:9.1e} {taken:7d} {rejected:5d} {err:10.3e} {perr:10.3e} {wall:8.3f}")


if __name__ == "__main__":
    sys.exit(main())
