#!/usr/bin/env python3
"""FRF error of fibre-angle pROMs along a fine angle sweep (thesis Fig. 3.22 and 3.24).

For SOL PROM decks that differ only in the THETA box of one PCOMP (e.g.
decks/prom/l2r_composite_prom_theta_90.dat and _45.dat):
1. build each pROM (``paraflex run``);
2. at each angle of the sweep (inside and outside the boxes) build the non-parametric ROM of that
   angle: the first deck with the PCOMP plies at ±Θ and a zero-width box (LOW = HIGH = Θ), one
   sample (every sample of a zero-width box is the same point) — the same NMODES + static modes;
3. compare the FRFs (SOL 111 on each artifact, FREQ1 over the PMOR band) with the thesis's
   average error mean_l |(|H_pROM| − |H_ROM|)| / |H_ROM| for one input = output DOF;
4. plot error against Θ per pROM with its box and LHS samples → PNG; the table → CSV.

    .venv/bin/python tools/prom/angle_sweep.py decks/prom/l2r_composite_prom_theta_90.dat \
        decks/prom/l2r_composite_prom_theta_45.dat --pair 1000002:3 --step 2 \
        -o docs/img/l2r_composite_prom_angle_sweep.png
"""
from __future__ import annotations

import argparse
import csv
import re
import tempfile
from pathlib import Path

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from paraflex_tools.prom_decks import absolute_includes, frf, rom_deck_theta, theta_box  # noqa: E402
from paraflex_tools.runner import default_binary, run_checked  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("decks", type=Path, nargs="+")
    ap.add_argument("--pair", required=True, help="input = output DOF, GRID:component")
    ap.add_argument("--step", type=float, default=2.0, help="sweep step in degrees over [0, 90]")
    ap.add_argument("--lines", type=int, default=250)
    ap.add_argument("--paraflex", default=str(default_binary()))
    ap.add_argument("-o", "--output", type=Path, required=True)
    args = ap.parse_args()
    texts = [absolute_includes(d.read_text(), d.parent) for d in args.decks]
    boxes = [theta_box(t, d) for t, d in zip(texts, args.decks)]
    fmax = float(re.search(r"^PMOR,\d+,\d+,\d+,([^,\n]+)", texts[0], flags=re.M).group(1))
    angles = np.arange(0.0, 90.0 + 1e-9, args.step)
    errors = np.zeros((len(args.decks), len(angles)))
    samples, sizes = [], []
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        proms = []
        for i, (text, deck) in enumerate(zip(texts, args.decks)):
            built = work / f"prom{i}.dat"
            built.write_text(text)
            out = work / f"prom{i}.h5"
            run_checked(built, out, args.paraflex)
            with h5py.File(out, "r") as f:
                samples.append(f["prom/build/samples"][:, 0])
                sizes.append(int(f["prom"].attrs["n_red"]))
            proms.append(out)
            print(f"{deck.name}: pROM size {sizes[-1]}", flush=True)
        name, pid = boxes[0][0], boxes[0][1]
        for a, theta in enumerate(angles):
            deck = work / "rom.dat"
            deck.write_text(rom_deck_theta(texts[0], pid, theta))
            rom = work / "rom.h5"
            run_checked(deck, rom, args.paraflex)
            pval = f"PVAL,1,{name},{theta!r}\n"
            _, h_rom = frf(args.paraflex, rom, pval, (0.0, fmax), args.lines, work, args.pair)
            for i, prom in enumerate(proms):
                _, h_prom = frf(args.paraflex, prom, pval, (0.0, fmax), args.lines, work, args.pair)
                errors[i, a] = np.mean(np.abs(np.abs(h_prom) - np.abs(h_rom)) / np.abs(h_rom))
            print(f"Θ = {theta:5.1f}°: " + ", ".join(f"{d.stem} {errors[i, a]:.2e}" for i, d in enumerate(args.decks)), flush=True)
    args.output.parent.mkdir(parents=True, exist_ok=True)
    with open(args.output.with_suffix(".csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["theta_deg"] + [f"{d.stem}_error" for d in args.decks])
        for a, theta in enumerate(angles):
            w.writerow([f"{theta:.2f}"] + [f"{errors[i, a]:.6e}" for i in range(len(args.decks))])
    fig, ax = plt.subplots(figsize=(7.0, 4.4))
    colours = ["tab:blue", "tab:orange", "tab:green", "tab:red"]
    for i, d in enumerate(args.decks):
        c = colours[i % len(colours)]
        _, _, lo, hi = boxes[i]
        ax.semilogy(angles, errors[i], "-o", ms=3, color=c, label=f"pROM Θ ∈ [{lo:g}°, {hi:g}°], size {sizes[i]}")
        ax.axvspan(lo, hi, color=c, alpha=0.08)
        ax.plot(samples[i], np.full_like(samples[i], errors[i].min() / 3), "*", color=c, ms=8)
    ax.set_xlabel("Θ (deg)")
    ax.set_ylabel("average |FRF| error, pROM vs ROM")
    ax.set_title(f"{args.decks[0].stem.rsplit('_', 1)[0]}: FRF {args.pair} / {args.pair}, 0–{fmax:g} Hz (stars: LHS samples)")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(args.output, dpi=110)
    print(f"wrote {args.output} and {args.output.with_suffix('.csv')}")


if __name__ == "__main__":
    main()
