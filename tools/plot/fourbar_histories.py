#!/usr/bin/env python3
"""Pictures of the four-bar case study (thesis §4.4, docs/fourbar.md) from paraflex runs:

- ``fourbar_mechanism.png``: the mechanism at t = 0 (ground pivots A, D; joints B, C; links IC,
  C, OC) with the path of the coupler joint C over the run;
- ``fourbar_pfmb_vs_fmb.png``: pFMB against FMB histories like thesis Fig. 4.6–4.11 — deviation
  of C from the rigid twin, acceleration of C, strain gauges of IC and OC (steel, parameter set
  1: E 60 %, ρ 140 %) and of the composite coupler at Θ = 0° — each with its eq. 4.11 error
  ‖y_pFMB(t) − y_FMB(t)‖ / max_t ‖y_FMB‖ on a second axis.

The pFMB is the decks/fourbar/fmb artifacts evaluated at p (PVAL); the FMB is built from
non-parametric ROMs of the same meshes reduced at p (the pROM deck with its material set to p,
its PMPAR range shrunk to the point and one sample), as tests/fourbar.rs builds it.

    .venv/bin/python tools/plot/fourbar_histories.py [--paraflex BIN] [--out docs/img]
        [--duration 1.0] [--work DIR]

Runs about a minute with the release binary (`make fourbar-plots`).
"""
from __future__ import annotations

import argparse
import shutil
import tempfile
from pathlib import Path

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from paraflex_tools.runner import find_binary, run_checked  # noqa: E402

ROOT = Path(__file__).resolve().parents[2]
DECKS = ROOT / "decks/fourbar/fmb"
E_REF, RHO_REF = 201.99e9, 7990.0
STEEL_PVAL = "PVAL,1,IC.E,201.99E9,IC.RHO,7990.,C.E,201.99E9,C.RHO\n,7990.,OC.E,201.99E9,OC.RHO,7990."
LINKS = {"crank": "crank_prom.dat", "coupler": "coupler_prom.dat",
         "output_crank": "output_crank_prom.dat"}
PIVOTS = {"A": (0.0, 0.0), "B": (0.0, 0.1), "C": (0.28898, 0.29746), "D": (0.25, 0.0)}


def edit(text: str, old: str, new: str) -> str:
    if old not in text:
        raise ValueError(f"{old!r} not in the deck")
    return text.replace(old, new)


def deck(name: str) -> str:
    """The deck text, its mesh INCLUDEs (pROM decks) resolved against the repository."""
    return (DECKS / name).read_text().replace("'../../../meshes/", f"'{ROOT / 'meshes'}/")


def at_point(text: str, samples: int, pmpars: list[tuple[str, str]]) -> str:
    """A pROM deck reduced at one parameter point: PMPAR ranges shrunk to it, one sample."""
    text = edit(text, f"PMOR,1,{samples},", "PMOR,1,1,")
    for old, new in pmpars:
        text = edit(text, old, new)
    return text


def steel_at(name: str, e: float, rho: float) -> str:
    text = edit(deck(name), "MAT1,1,201.99E9,,0.34,7990.0", f"MAT1,1,{e:e},,0.34,{rho!r}")
    return at_point(text, 2, [("PMPAR,1,E,E,1,121.194E9,282.786E9", f"PMPAR,1,E,E,1,{e:e},{e:e}"),
                              ("PMPAR,2,RHO,RHO,1,4794.,11186.", f"PMPAR,2,RHO,RHO,1,{rho!r},{rho!r}")])


def composite_at(theta: float) -> str:
    text = edit(deck("coupler_composite_prom.dat"), ",2,0.00025,20.0,,2,0.00025,-20.0,",
                f",2,0.00025,{theta!r},,2,0.00025,{-theta!r},")
    return at_point(text, 6, [("PMPAR,1,THETA,THETA,1,0.,90.",
                               f"PMPAR,1,THETA,THETA,1,{theta!r},{theta!r}")])


def build(directory: Path, artifacts: dict[str, str], binary: Path) -> None:
    """Writes each deck text as ``<artifact>.dat`` in ``directory`` and runs it to ``<artifact>.h5``."""
    directory.mkdir(parents=True, exist_ok=True)
    for artifact, text in artifacts.items():
        path = directory / f"{artifact}.dat"
        path.write_text(text)
        run_checked(path, directory / f"{artifact}.h5", binary)


def simulate(directory: Path, fmb: str, pval: tuple[str, str], steps: int, binary: Path) -> dict:
    text = edit(edit(fmb, *pval), "TSTEP,1,1000,1.e-3,1", f"TSTEP,1,{steps},1.e-3,1")
    shutil.copy(DECKS / "drive.csv", directory / "drive.csv")
    path = directory / "fourbar.dat"
    path.write_text(text)
    run_checked(path, directory / "fourbar.h5", binary)
    with h5py.File(directory / "fourbar.h5") as f:
        g = f["results/1/fmb"]
        return {"t": g["time"][:], **{k: g[f"sensors/{k}"][:] for k in g["sensors"]}}


def error_4_11(p: np.ndarray, f: np.ndarray) -> np.ndarray:
    """Eq. 4.11 over time; rows are samples, columns components."""
    p, f = np.atleast_2d(p.T).T, np.atleast_2d(f.T).T
    return np.linalg.norm(p - f, axis=1) / np.linalg.norm(f, axis=1).max()


def run_cases(work: Path, steps: int, binary: Path) -> dict:
    e, rho = 0.6 * E_REF, 1.4 * RHO_REF
    steel_pval = (STEEL_PVAL, f"PVAL,1,IC.E,{e:e},IC.RHO,{rho!r},C.E,{e:e},C.RHO\n"
                              f",{rho!r},OC.E,{e:e},OC.RHO,{rho!r}")
    build(work / "pfmb", {a: deck(d) for a, d in LINKS.items()}
          | {"coupler_composite": deck("coupler_composite_prom.dat")}, binary)
    build(work / "steel", {a: steel_at(d, e, rho) for a, d in LINKS.items()}, binary)
    cranks = {a: steel_at(LINKS[a], E_REF, RHO_REF) for a in ("crank", "output_crank")}
    build(work / "composite", cranks | {"coupler_composite": composite_at(0.0)}, binary)
    steel, composite = deck("fourbar_steel.dat"), deck("fourbar_composite.dat")
    theta = ("PVAL,1,C.THETA,45.", "PVAL,1,C.THETA,0.")
    return {
        "steel": (simulate(work / "pfmb", steel, steel_pval, steps, binary),
                  simulate(work / "steel", steel, steel_pval, steps, binary)),
        "composite": (simulate(work / "pfmb", composite, theta, steps, binary),
                      simulate(work / "composite", composite, theta, steps, binary)),
    }


def plot_mechanism(run: dict, out: Path) -> None:
    fig, ax = plt.subplots(figsize=(5.2, 4.6))
    p = {k: np.array(v) for k, v in PIVOTS.items()}
    for (a, b), name in zip((("A", "B"), ("B", "C"), ("D", "C")), ("IC", "C", "OC")):
        ax.plot(*np.c_[p[a], p[b]], lw=5, solid_capstyle="round", label=f"{name} (t = 0)")
    ax.plot(*np.c_[p["A"], p["D"]], "k--", lw=1, label="ground link")
    ax.plot(run["CX"], run["CY"], "k", lw=0.8, label="path of C (pFMB)")
    for k, v in p.items():
        ax.plot(*v, "ko", ms=5)
        ax.annotate(k, v, textcoords="offset points", xytext=(6, -12))
    ax.annotate("", xy=(0.32, 0.05), xytext=(0.32, 0.13), arrowprops={"arrowstyle": "->"})
    ax.text(0.325, 0.09, "g")
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title("four-bar (thesis §4.4): drive at A, 10 Hz, 0 → 20° → 0", fontsize=9)
    ax.legend(fontsize=7, loc="upper left")
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)


def plot_histories(cases: dict, out: Path) -> None:
    (sp, sf), (cp, cf) = cases["steel"], cases["composite"]
    accel = lambda r: np.c_[r["AX"], r["AY"]]  # noqa: E731
    panels = [
        ("deviation of C (mm), steel set 1", sp, sf, "CDEV", 1e3),
        ("acceleration of C (m/s²), steel set 1", sp, sf, accel, 1.0),
        ("strain IC (µε), steel set 1", sp, sf, "ICEPS", 1e6),
        ("strain OC (µε), steel set 1", sp, sf, "OCEPS", 1e6),
        ("deviation of C (mm), composite Θ = 0°", cp, cf, "CDEV", 1e3),
        ("strain C (µε), composite Θ = 0°", cp, cf, "CEPS", 1e6),
    ]
    fig, axes = plt.subplots(3, 2, figsize=(10, 8.5), sharex=True)
    for ax, (title, p, f, key, scale) in zip(axes.ravel(), panels):
        yp, yf = (key(p), key(f)) if callable(key) else (p[key], f[key])
        shown = (lambda y: np.linalg.norm(y, axis=1)) if yp.ndim == 2 else (lambda y: y)
        ax.plot(f["t"], scale * shown(yf), "k", lw=1.0, label="FMB (ROMs at p)")
        ax.plot(p["t"], scale * shown(yp), "C1--", lw=1.0, label="pFMB")
        ax.set_title(title + (" (|a|)" if yp.ndim == 2 else ""), fontsize=9)
        err = ax.twinx()
        err.plot(p["t"], 100 * error_4_11(yp, yf), "C3", lw=0.6, alpha=0.7)
        err.set_ylabel("eq. 4.11 error (%)", color="C3", fontsize=8)
        err.tick_params(axis="y", labelcolor="C3", labelsize=7)
        ax.tick_params(labelsize=7)
    axes[0, 0].legend(fontsize=7, loc="upper left")
    for ax in axes[-1]:
        ax.set_xlabel("t (s)")
    fig.suptitle("four-bar pFMB against FMB (thesis Fig. 4.6–4.11), BDF1, Δt = 1 ms", fontsize=10)
    fig.tight_layout()
    fig.savefig(out, dpi=110)
    plt.close(fig)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--paraflex", help="paraflex binary (default: the release build)")
    ap.add_argument("--out", type=Path, default=ROOT / "docs/img")
    ap.add_argument("--duration", type=float, default=1.0, help="seconds of the drive (≤ 1)")
    ap.add_argument("--work", type=Path, help="keep the runs here (default: a temp directory)")
    args = ap.parse_args()
    binary = find_binary(args.paraflex)
    steps = round(args.duration / 1e-3)
    with tempfile.TemporaryDirectory() as tmp:
        cases = run_cases(args.work or Path(tmp), steps, binary)
    args.out.mkdir(parents=True, exist_ok=True)
    plot_mechanism(cases["steel"][0], args.out / "fourbar_mechanism.png")
    plot_histories(cases, args.out / "fourbar_pfmb_vs_fmb.png")
    for name in ("fourbar_mechanism.png", "fourbar_pfmb_vs_fmb.png"):
        print(args.out / name)


if __name__ == "__main__":
    main()
