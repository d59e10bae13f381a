#!/usr/bin/env python3
"""Draw a ``SOL OPTIMIZE`` study (``/results/<subcase>/optimize``) to PNG, like thesis
Fig. 6.4-6.11: the objective space (every design, infeasible ones hollow, failed ones left
out, the Pareto front joined and the representative designs labelled) and the hypervolume
after each evaluation.

    .venv/bin/python tools/optimize/plot_study.py study.h5 [-o study.png] [--subcase 1]
"""
from __future__ import annotations

import argparse
from pathlib import Path

import h5py
import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def names(attr) -> list[str]:
    """An HDF5 string-list attribute as Python strings."""
    return [v.decode() if isinstance(v, bytes) else str(v) for v in np.atleast_1d(attr)]


def read_study(path: Path, subcase: str) -> dict:
    """The datasets and attributes of one study group."""
    with h5py.File(path, "r") as f:
        g = f[f"results/{subcase}/optimize"]
        study = {k: g[k][()] for k in ("designs", "responses", "feasible", "pareto", "hypervolume")}
        study["objectives"] = names(g.attrs["objectives"])
        study["responses_names"] = names(g.attrs["responses"])
        study["representatives"] = (
            {label: int(r.attrs["design"]) for label, r in g["representative"].items()}
            if "representative" in g
            else {}
        )
    return study


def draw(study: dict, title: str) -> plt.Figure:
    """The front (first two objectives) and the hypervolume history side by side."""
    responses = np.atleast_2d(study["responses"])
    columns = [study["responses_names"].index(o) for o in study["objectives"][:2]]
    feasible = study["feasible"].astype(bool)
    ok = np.all(np.isfinite(responses[:, columns]), axis=1)
    x, y = responses[:, columns[0]], responses[:, columns[1]]
    fig, (front, history) = plt.subplots(1, 2, figsize=(10, 4.2))
    front.scatter(x[feasible], y[feasible], s=18, color="tab:blue", label="feasible")
    hollow = ~feasible & ok
    if hollow.any():
        front.scatter(x[hollow], y[hollow], s=18, facecolors="none", edgecolors="tab:red", label="infeasible")
    pareto = np.asarray(study["pareto"], dtype=int)
    order = pareto[np.argsort(x[pareto])]
    front.plot(x[order], y[order], "k-", lw=1, marker="o", ms=6, mfc="none", label="Pareto front")
    labels: dict[int, list[str]] = {}
    for label, i in study["representatives"].items():
        labels.setdefault(i, []).append(label)
    for i, names_of_i in labels.items():
        front.annotate(", ".join(sorted(names_of_i)), (x[i], y[i]), textcoords="offset points", xytext=(5, 5), fontsize=8)
    front.set_xlabel(study["objectives"][0])
    front.set_ylabel(study["objectives"][1] if len(columns) > 1 else "")
    front.legend(fontsize=8)
    front.set_title(title)
    hv = study["hypervolume"]
    history.plot(np.arange(1, len(hv) + 1), hv, "-", color="tab:green")
    history.set_xlabel("evaluations")
    history.set_ylabel("hypervolume of the feasible front")
    history.grid(True, alpha=0.3)
    fig.tight_layout()
    return fig


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("file", type=Path)
    ap.add_argument("-o", "--output", type=Path, help="PNG (default: <file stem>_study.png)")
    ap.add_argument("--subcase", default="1")
    args = ap.parse_args()
    study = read_study(args.file, args.subcase)
    if len(study["objectives"]) < 2:
        raise SystemExit(f"{args.file}: the study has one objective; the front needs two")
    fig = draw(study, f"{args.file.name}: {len(study['hypervolume'])} designs")
    out = args.output or args.file.with_name(f"{args.file.stem}_study.png")
    fig.savefig(out, dpi=120)
    print(out)


if __name__ == "__main__":
    main()
