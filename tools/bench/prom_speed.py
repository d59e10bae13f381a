#!/usr/bin/env python3
"""pROM speed against error (thesis §3.5–3.6): per case

- build: pROM build time split into sampling (local bases), MAC filter + SVD, projection and
  size selection (`/prom/build/timings`), the size, and the FRF change (eq. 3.35) per size;
- re-reduction: the time to build the non-parametric ROM of the full model at a new p (the same
  deck with a zero-width box and one sample: element matrices, assembly, constraints, one local
  basis, SVD, projection; size selection and file output left out), from `paraflex run`'s timings;
- evaluation: the time of `Prom::evaluate` (M_r, C_r, K_r and ∂/∂p_j) at random points of the
  box (`examples/prom_eval.rs`);
- error: the thesis's average FRF error mean |(|H_pROM| − |H_ROM|)| / |H_ROM| at three points
  inside the box (quarter points of the box diagonal and its centre), one input = output DOF.

    make bench-prom          # or:
    .venv/bin/python tools/bench/prom_speed.py [--cases blade40,blade10,l2r90,l2r45]

needs `cargo build --release` and `cargo build --release --example prom_eval` (make does both).
"""
from __future__ import annotations

import argparse
import re
import subprocess
import tempfile
from pathlib import Path

import h5py
import numpy as np

from paraflex_tools import REPO
from paraflex_tools.prom_decks import (absolute_includes, frf, inline_material, rom_deck_e_rho, rom_deck_theta,
                                       theta_box)
from paraflex_tools.results import texts
from paraflex_tools.runner import default_binary, run_checked

CASES = {
    "blade40": ("decks/blade/blade_prom_e_rho.dat", "71:3"),
    "blade10": ("decks/prom/blade_prom_e_rho_10.dat", "71:3"),
    "l2r90": ("decks/prom/l2r_composite_prom_theta_90.dat", "1000002:3"),
    "l2r45": ("decks/prom/l2r_composite_prom_theta_45.dat", "1000002:3"),
}
SKIPPED_PHASES = ("output", "sensor rows")


def run_timed(paraflex: str, deck: Path, out: Path) -> dict[str, float]:
    line = next(l for l in run_checked(deck, out, paraflex).stdout.splitlines() if l.startswith("timings:"))
    body = line[len("timings:"):].split(";")[0]
    return {name.strip(): float(sec) for name, sec in re.findall(r"([^,]+?) ([0-9.eE+-]+) s", body)}


def build_log(path: Path):
    with h5py.File(path, "r") as f:
        b = f["prom/build"]
        phases = texts(b.attrs["timing_phases"])
        return (dict(zip(phases, b["timings"][:])), int(f["prom"].attrs["n_red"]), int(f["prom"].attrs["n_full"]),
                list(zip(b["size_history"][:].astype(int), b["error_history"][:])), texts(f["prom"].attrs["params"]))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--cases", default=",".join(CASES))
    ap.add_argument("--evaluations", type=int, default=2000)
    ap.add_argument("--paraflex", default=str(default_binary()))
    ap.add_argument("--prom-eval", default=str(default_binary().parent / "examples" / "prom_eval"))
    args = ap.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        for case in args.cases.split(","):
            deck_path, pair = CASES[case]
            deck_path = REPO / deck_path
            text = absolute_includes(deck_path.read_text(), deck_path.parent)
            built = work / f"{case}.dat"
            built.write_text(text)
            prom = work / f"{case}.h5"
            run_timed(args.paraflex, built, prom)
            phases, n_red, n_full, history, params = build_log(prom)
            fmax = float(re.search(r"^PMOR,\d+,\d+,\d+,([^,\n]+)", text, flags=re.M).group(1))
            if "THETA" in params:
                name, pid, lo, hi = theta_box(text, deck_path)
                points = [lo + t * (hi - lo) for t in (0.25, 0.5, 0.75)]
                decks = [(rom_deck_theta(text, pid, th), f"PVAL,1,{name},{th!r}\n") for th in points]
            else:
                pm = dict((k, (n, int(r), float(a), float(b))) for _, n, k, r, a, b in re.findall(r"^PMPAR,(\d+),(\w+),(\w+),(\d+),([^,\n]+),([^,\n]+)$", text, flags=re.M))
                mid = pm["E"][1]
                text = inline_material(text, mid)
                box = [(pm[k][2], pm[k][3]) for k in ("E", "RHO")]
                corners = [(0.25, 0.75), (0.5, 0.5), (0.75, 0.25)]
                decks = []
                for te, tr in corners:
                    e, rho = box[0][0] + te * (box[0][1] - box[0][0]), box[1][0] + tr * (box[1][1] - box[1][0])
                    decks.append((rom_deck_e_rho(text, mid, e, rho), f"PVAL,1,{pm['E'][0]},{e!r},{pm['RHO'][0]},{rho!r}\n"))
            errors, rereduce = [], []
            for k, (rom_text, pval) in enumerate(decks):
                deck = work / f"{case}_rom{k}.dat"
                deck.write_text(rom_text)
                rom = work / f"{case}_rom{k}.h5"
                t = run_timed(args.paraflex, deck, rom)
                rom_phases, *_ = build_log(rom)
                rereduce.append(sum(v for n, v in t.items() if not any(s in n for s in SKIPPED_PHASES)) - rom_phases.get("size selection", 0.0))
                _, h_rom = frf(args.paraflex, rom, pval, (0.0, fmax), 250, work, pair)
                _, h_prom = frf(args.paraflex, prom, pval, (0.0, fmax), 250, work, pair)
                errors.append(float(np.mean(np.abs(np.abs(h_prom) - np.abs(h_rom)) / np.abs(h_rom))))
            r = subprocess.run([args.prom_eval, str(prom), str(args.evaluations)], capture_output=True, text=True, check=True)
            evaluation = float(re.search(r"seconds_per_evaluation ([0-9.eE+-]+)", r.stdout).group(1))
            row = dict(case=case, n_full=n_full, n_red=n_red, sampling=phases.get("local bases", 0.0), svd=phases.get("MAC filter and SVD", 0.0),
                       projection=phases.get("projection", 0.0), selection=phases.get("size selection", 0.0), rereduce=float(np.median(rereduce)),
                       evaluation=evaluation, error=max(errors), history=history)
            rows.append(row)
            print(f"{case}: n_full {n_full}, n_red {n_red}; build: sampling {row['sampling']:.2f} s, MAC+SVD {row['svd']:.2f} s, "
                  f"projection {row['projection']:.2f} s, size selection {row['selection']:.2f} s; re-reduction {row['rereduce']:.2f} s; "
                  f"evaluation {evaluation:.2e} s (× {row['rereduce'] / evaluation:.1e}); FRF error in the box ≤ {row['error']:.1e}", flush=True)
            print("  size → FRF change (eq. 3.35): " + ", ".join(f"{s} {e:.1e}" for s, e in history), flush=True)
    print("\n| case | n_full | n_red | build: sampling / SVD / projection / size selection (s) | re-reduction (s) | evaluation (s) | speed-up | FRF error in the box |")
    print("|---|---|---|---|---|---|---|---|")
    for r in rows:
        print(f"| {r['case']} | {r['n_full']} | {r['n_red']} | {r['sampling']:.2f} / {r['svd']:.2f} / {r['projection']:.2f} / {r['selection']:.2f} | "
              f"{r['rereduce']:.2f} | {r['evaluation']:.1e} | {r['rereduce'] / r['evaluation']:.1e} | {r['error']:.1e} |")


if __name__ == "__main__":
    main()
