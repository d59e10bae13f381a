#!/usr/bin/env python3
"""Reference for the linear cross-check of paraflex's Kalman filter (src/estimate/filter.rs,
test `linear_case_equals_filterpy`): filterpy's KalmanFilter (predict: P = F P Fᵀ + Q; update:
Joseph form) on the discrete matrices paraflex uses.

    PARAFLEX_WRITE_KF_CASE=/tmp/kf_case.json cargo test --lib linear_case_equals_filterpy
    .venv/bin/python tools/estimate/filterpy_reference.py /tmp/kf_case.json \
        -o reference/estimate/filterpy_linear.json

The case (F, H, diagonal Q, R, P0, x0, measurements z) is copied into the output next to the
filtered states x (one row per step), so the test can check that the reference belongs to its
matrices.
"""
from __future__ import annotations

import argparse
import json

import filterpy
import numpy as np
from filterpy.kalman import KalmanFilter


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("case")
    ap.add_argument("-o", "--output", required=True)
    args = ap.parse_args()
    case = json.load(open(args.case))
    F, H = np.array(case["F"]), np.array(case["H"])
    n, m = F.shape[0], H.shape[0]
    kf = KalmanFilter(dim_x=n, dim_z=m)
    kf.F, kf.H = F, H
    kf.Q, kf.R = np.diag(case["Q_diag"]), np.diag(case["R_diag"])
    kf.x = np.array(case["x0"], dtype=float).reshape(n, 1)
    kf.P = np.diag(case["P0_diag"])
    states = []
    for z in case["z"]:
        kf.predict()
        kf.update(np.array(z, dtype=float).reshape(m, 1))
        states.append(kf.x.ravel().tolist())
    out = {"provenance": f"filterpy {filterpy.__version__} KalmanFilter, tools/estimate/filterpy_reference.py", "case": case, "x": states}
    json.dump(out, open(args.output, "w"), indent=1)
    print(f"wrote {args.output}: {len(states)} steps, state size {n}")


if __name__ == "__main__":
    main()
