#!/usr/bin/env python3
"""FRF error of a pROM against non-parametric ROMs over a parameter grid (thesis Fig. 3.11/3.13).

For a SOL PROM deck with two PMPARs on one MAT1 (E and RHO, e.g. decks/blade/blade_prom_e_rho.dat):
1. build the pROM (``paraflex run deck -o prom.h5``);
2. at each point of an N × N grid of (E, RHO) factors of the nominal values (reaching beyond the
   sampled box), build the non-parametric ROM of that point: the same deck with the MAT1 at the
   point and a zero-width box (LOW = HIGH = value: every LHS sample is the point, the same
   NMODES + static modes) — the thesis's "standard, non-parametric ROM";
3. compute both FRFs (SOL 111 on each artifact, FREQ1 over the PMOR band) and the thesis's average
   error mean_l (|H_pROM| − |H_ROM|) / |H_ROM| for one input/output pair, in absolute value;
4. plot the map (log colour), the sampled box and the LHS samples → PNG; write the table → CSV.

    .venv/bin/python tools/prom/error_map.py decks/blade/blade_prom_e_rho.dat --pair 71:3 \
        --grid 11 --span 0.3 1.7 --paraflex target/release/paraflex -o docs/img/blade_prom_error_map.png
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

from paraflex_tools.prom_decks import absolute_includes, frf, inline_material, rom_deck_e_rho  # noqa: E402
from paraflex_tools.results import texts  # noqa: E402
from paraflex_tools.runner import default_binary, run_checked  # noqa: E402


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("deck", type=Path)
    ap.add_argument("--pair", required=True, help="input = output DOF, GRID:component")
    ap.add_argument("--grid", type=int, default=11)
    ap.add_argument("--span", type=float, nargs=2, default=(0.3, 1.7), help="factor range of the nominal values")
    ap.add_argument("--lines", type=int, default=250)
    ap.add_argument("--paraflex", default=str(default_binary()))
    ap.add_argument("-o", "--output", type=Path, required=True)
    args = ap.parse_args()
    text = absolute_includes(args.deck.read_text(), args.deck.parent)
    pmpar = re.findall(r"^PMPAR,(\d+),(\w+),(\w+),(\d+),([^,\n]+),([^,\n]+)$", text, flags=re.M)
    kinds = {kind: (name, int(ref), float(lo), float(hi)) for _, name, kind, ref, lo, hi in pmpar}
    if set(kinds) != {"E", "RHO"} or kinds["E"][1] != kinds["RHO"][1]:
        raise SystemExit("the deck needs PMPAR E and PMPAR RHO on one MAT1")
    mid = kinds["E"][1]
    mat_re = rf"^MAT1,{mid},([^,]+),([^,]*),([^,]+),([^,\n]+)"
    text = inline_material(text, mid)
    mat = re.search(mat_re, text, flags=re.M)
    if mat is None:
        raise SystemExit(f"MAT1 {mid} not found in free-field form in the deck or its includes")
    e0, rho0 = float(mat.group(1)), float(mat.group(4))
    pmor = re.search(r"^PMOR,\d+,\d+,\d+,([^,\n]+)", text, flags=re.M)
    fmax = float(pmor.group(1))
    factors = np.linspace(args.span[0], args.span[1], args.grid)
    errors = np.zeros((args.grid, args.grid))
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        prom = work / "prom.h5"
        built = work / "prom.dat"
        built.write_text(text)
        run_checked(built, prom, args.paraflex)
        with h5py.File(prom, "r") as f:
            samples = f["prom/build/samples"][:]
            names = texts(f["prom"].attrs["params"])
        ie, ir = names.index(kinds["E"][0].upper()), names.index(kinds["RHO"][0].upper())
        for a, fe in enumerate(factors):
            for b, fr in enumerate(factors):
                e, rho = e0 * fe, rho0 * fr
                deck = work / "rom.dat"
                deck.write_text(rom_deck_e_rho(text, mid, e, rho))
                rom = work / "rom.h5"
                run_checked(deck, rom, args.paraflex)
                pval = f"PVAL,1,{kinds['E'][0]},{e!r},{kinds['RHO'][0]},{rho!r}\n"
                _, h_rom = frf(args.paraflex, rom, pval, (0.0, fmax), args.lines, work, args.pair)
                _, h_prom = frf(args.paraflex, prom, pval, (0.0, fmax), args.lines, work, args.pair)
                errors[b, a] = np.mean(np.abs(np.abs(h_prom) - np.abs(h_rom)) / np.abs(h_rom))
                print(f"E × {fe:.2f}, ρ × {fr:.2f}: average FRF error {errors[b, a]:.2e}", flush=True)
    args.output.parent.mkdir(parents=True, exist_ok=True)
    with open(args.output.with_suffix(".csv"), "w", newline="") as f:
        w = csv.writer(f)
        w.writerow(["E_factor", "RHO_factor", "average_frf_error"])
        for a, fe in enumerate(factors):
            for b, fr in enumerate(factors):
                w.writerow([f"{fe:.4f}", f"{fr:.4f}", f"{errors[b, a]:.6e}"])
    fig, ax = plt.subplots(figsize=(6.4, 5.2))
    im = ax.pcolormesh(factors, factors, np.log10(errors), shading="nearest", cmap="viridis")
    fig.colorbar(im, ax=ax, label="log10 average |FRF| error (pROM vs ROM)")
    lo_e, hi_e = kinds["E"][2] / e0, kinds["E"][3] / e0
    lo_r, hi_r = kinds["RHO"][2] / rho0, kinds["RHO"][3] / rho0
    ax.add_patch(plt.Rectangle((lo_e, lo_r), hi_e - lo_e, hi_r - lo_r, fill=False, ec="lightgray", lw=2, label="sampled box"))
    ax.plot(samples[:, ie] / e0, samples[:, ir] / rho0, "r*", ms=10, label="LHS samples")
    ax.set_xlabel("E / E nominal")
    ax.set_ylabel("ρ / ρ nominal")
    ax.set_title(f"{args.deck.stem}: FRF {args.pair} / {args.pair}, 0–{fmax:g} Hz")
    ax.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    fig.savefig(args.output, dpi=110)
    print(f"wrote {args.output} and {args.output.with_suffix('.csv')}")


if __name__ == "__main__":
    main()
