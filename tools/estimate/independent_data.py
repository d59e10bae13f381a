#!/usr/bin/env python3
"""SOL ESTIMATE on measurements that do not come from its own integrator: the small plate of
decks/estimate (pROM in E and RHO, the 20 Hz sine of 5 N at the tip input 14:3, 0.1 ms, 0.5 s,
noise 1e-7 m on DISP and 1e-3 m/s² on ACCEL), with the data made two ways:

* ``bdf1``: paraflex's SOL 112 on the pROM (BDF1, the filter's own prediction, thesis eq. 8.22):
  what tests/estimate.rs and the thesis's §8.6 use;
* ``exact``: the exact response of the same pROM at the true point
  (``paraflex_tools.prom.Prom.response``: no time-discretization error), as a real structure
  would give.

For each, the E-only and E-and-RHO cases of tests/estimate.rs (same guesses, δ, sensors) are run
with each prediction of the filter (EKF PREDICT: BDF1 as the thesis, TRAP the trapezoidal rule,
the default) for several EKF QSTATE values (the process noise of q and q̇; default machine ε,
thesis §8.5.2), and the average error over the last 20 % is printed against Table 8.2's bound.

    .venv/bin/python tools/estimate/independent_data.py [--paraflex target/release/paraflex]
        [--predict BDF1 TRAP] [--qstate 2.2e-16 1e-14 1e-12 1e-10]
"""
from __future__ import annotations

import argparse
import math
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

from paraflex_tools import REPO, runner

DT, STEPS = 1e-4, 5000
CASES = {
    "E": ("EKFPAR,1,E,2.5E11,1.E-3\n", ["D_TIP_A,1e-7", "D_MID,1e-7"], 0.05),
    "E RHO": ("EKFPAR,1,E,2.5E11,1.\nEKFPAR,1,RHO,5460.,1.\n", ["D_TIP_A,1e-7", "D_MID,1e-7", "A_TIP,1e-3"], 0.5),
}
LOAD = "TLOAD1,7,8,,,9\nDAREA,8,14,3,1.\nTABLEF,9,'load.csv',time,force\n"


def run(binary: Path, work: Path, name: str, text: str) -> str:
    (work / f"{name}.dat").write_text(text)
    return runner.run_checked(work / f"{name}.dat", work / f"{name}.h5", binary, cwd=work).stdout


def averages(stdout: str) -> dict[str, float]:
    """Parameter → average error [%] of the run's error table."""
    table = stdout.split("error over the last 20 %")[1]
    return {m.group(1): float(m.group(2)) for m in re.finditer(r"^\s+(E|RHO)\s+\S+\s+(\S+)\s+\S+$", table, re.M)}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--paraflex", default=None)
    ap.add_argument("--qstate", type=float, nargs="*", default=[2.2e-16, 1e-14, 1e-12, 1e-10])
    ap.add_argument("--predict", nargs="*", choices=["BDF1", "TRAP"], default=["BDF1", "TRAP"])
    args = ap.parse_args()
    binary = runner.find_binary(args.paraflex)
    work = Path(tempfile.mkdtemp(prefix="independent_data_"))
    for name in ("plate_prom.dat", "plate.bdf"):
        shutil.copy(REPO / "decks" / "estimate" / name, work / name)
    runner.run_checked(work / "plate_prom.dat", work / "prom.h5", binary, cwd=work)
    rows = (f"{k * DT!r},{5.0 * math.sin(2 * math.pi * 20.0 * k * DT)!r}\n" for k in range(STEPS + 2))
    (work / "load.csv").write_text("time,force\n" + "".join(rows))
    make = [sys.executable, str(REPO / "tools" / "estimate" / "make_measurements.py"), "--sigma", "DISP=1e-7",
            "--sigma", "ACCEL=1e-3", "--truth", "E=2e11", "--truth", "RHO=7800", "--seed", "13"]
    run(binary, work, "bdf1", f"SOL 112\nCEND\nROM = 'prom.h5'\nPVAL = 1\nTSTEP = 1\nDLOAD = 7\nBEGIN BULK\n"
        f"PVAL,1,E,2.E11,RHO,7800.\nTSTEP,1,{STEPS},{DT!r},1\nTINTEG,1,BDF1\n{LOAD}ENDDATA\n")
    subprocess.run([*make, str(work / "bdf1.h5"), "-o", str(work / "bdf1.csv")], check=True, capture_output=True)
    subprocess.run([*make, "--simulate", str(work / "prom.h5"), "--load", str(work / "load.csv"), "--dt", repr(DT),
                    "--steps", str(STEPS), "-o", str(work / "exact.csv")], check=True, capture_output=True)
    print(f"{'data':6} {'case':6} {'PREDICT':7} {'QSTATE':>8}  average error over the last 20 % [%] (bound)")
    for data in ("bdf1", "exact"):
        for case, (parameters, sensors, bound) in CASES.items():
            for predict in args.predict:
                for q in args.qstate:
                    meas = "".join(f"MEAS,2,{s.split(',')[0]},{s}\n" for s in sensors)
                    out = run(binary, work, "estimate",
                              f"SOL ESTIMATE\nCEND\nROM = 'prom.h5'\nESTIM = 1\nMEAS = 2\nTSTEP = 1\nDLOAD = 7\n"
                              f"BEGIN BULK\nTSTEP,1,{STEPS},{DT!r},1\nEKF,1,{q!r},,,,{predict}\n{parameters}"
                              f"MEASF,2,'{data}.csv',time\n{meas}{LOAD}ENDDATA\n")
                    errors = ", ".join(f"{k} {v:+.4f}" for k, v in averages(out).items())
                    print(f"{data:6} {case:6} {predict:7} {q:8.1e}  {errors}  (|avg| ≤ {bound})", flush=True)
    shutil.rmtree(work)


if __name__ == "__main__":
    main()
