"""Static validation of the Robolink pFMB (thesis §4.5.4.1, Fig. 4.32–4.33): the 19 × 19 grid
of M2, M3 ∈ [0°, 90°] (``decks/robot/fmb/robot_grid.dat``) with three sets of flexible bodies,

* ``pfmb``: the pROMs of ``decks/robot/fmb/*_prom.dat`` at their nominal parameters (the
  thesis's reference values);
* ``fmb``: the thesis's FMB, non-parametric ROMs of the same meshes reduced at those values
  (each pROM deck with its PMPAR box shrunk to the point and one sample keeping its whole
  local basis: ``paraflex_tools.prom_decks.rom_deck_e_rho``);
* ``fmb40``: the same ROMs with 40 instead of 10 normal modes per body, a reference closer to
  the full-order bodies (paraflex's FLEXB takes reduced bodies only), which measures what the
  22-DOF bases themselves leave out.

For each set it builds the artifacts, solves the grid (wall time of the grid solve from the
run's console), and compares the pFMB's EE deviation from the rigid twin (eq. 4.12) and the
L2r / L3r gauges with each reference as the error map of the thesis's figures,
|y_pFMB − y_ref| / max_grid |y_ref| (eq. 4.11 over the grid instead of the time). Writes the
maps ``docs/img/robot_map_values.png``, ``docs/img/robot_map_error_fmb.png``,
``docs/img/robot_map_error_fmb40.png`` and the summary ``reference/robot/static_map.json``.

Run: ``.venv/bin/python tools/robot/static_map.py [--paraflex BIN] [--work DIR]`` (a few
minutes with a debug build: three artifact sets and three grids).
"""
from __future__ import annotations

import argparse
import json
import re
import shutil
import time
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from paraflex_tools.prom_decks import rom_deck_e_rho  # noqa: E402
from paraflex_tools.results import read_poses  # noqa: E402
from paraflex_tools.runner import find_binary, run_checked  # noqa: E402

REPO = Path(__file__).resolve().parents[2]
DECKS = REPO / "decks" / "robot" / "fmb"
PROVENANCE = "tools/robot/static_map.py"
# artifact ← pROM deck, with its reference (E, ρ) (Tables 4.6, 4.8)
BODIES = {"plate": (28.8e9, 2630.0), "l1": (201.99e9, 7990.0), "l2": (201.99e9, 7990.0),
          "l3": (194.37e9, 7990.0)}
GRID_FILES = ("robot_grid.dat", "robot_bodies.inc", "robot_sensors.inc", "hold_tables.inc")
SENSORS = {"EEDEV": ("EE deviation", 1e3, "mm"), "EPS2": ("L2r strain", 1e6, "µε"),
           "EPS3": ("L3r strain", 1e6, "µε")}


def with_modes(text: str, modes: int) -> str:
    """The deck with NMODES of its PMOR set to ``modes``."""
    return re.sub(r"^(PMOR,\d+,\d+,)\d+", rf"\g<1>{modes}", text, flags=re.M)


def deck_text(name: str, variant: str) -> str:
    text = (DECKS / f"{name}_prom.dat").read_text()
    text = re.sub(r"INCLUDE\s+'([^']+)'",
                  lambda m: f"INCLUDE '{(DECKS / m.group(1)).resolve()}'", text)
    if variant == "pfmb":
        return text
    e, rho = BODIES[name]
    rom = rom_deck_e_rho(text, 1, e, rho)
    return with_modes(rom, 40) if variant == "fmb40" else rom


def build(variant: str, work: Path, binary: Path) -> dict:
    """Artifacts of ``variant`` and its grid run in ``work/variant``: the poses, timings."""
    d = work / variant
    d.mkdir(parents=True, exist_ok=True)
    t0 = time.perf_counter()
    for name in BODIES:
        deck = d / f"{name}_prom.dat"
        deck.write_text(deck_text(name, variant))
        run_checked(deck, d / f"{name}.h5", binary)
    build_s = time.perf_counter() - t0
    for f in GRID_FILES:
        shutil.copy(DECKS / f, d / f)
    res = run_checked(d / "robot_grid.dat", d / "grid.h5", binary)
    grid_s = float(re.search(r"multibody ([0-9.]+) s", res.stdout).group(1))
    poses = read_poses(d / "grid.h5", "1")
    return {"poses": poses, "build_s": build_s, "grid_s": grid_s,
            "newton": re.search(r"Newton: .*", res.stdout).group(0)}


def maps(poses) -> dict:
    return {k: poses.map(k) for k in SENSORS}


def draw(fields: dict, axes_deg, title: str, path: Path, percent: bool) -> None:
    fig, axs = plt.subplots(1, 3, figsize=(15, 4.2))
    x, y = axes_deg
    for ax, (key, (label, scale, unit)) in zip(axs, SENSORS.items()):
        values = fields[key] * (100.0 if percent else scale)
        mesh = ax.pcolormesh(x, y, values.T, shading="nearest", cmap="viridis")
        fig.colorbar(mesh, ax=ax, label="error (%)" if percent else f"{label} ({unit})")
        ax.set_xlabel("M2 (deg)")
        ax.set_ylabel("M3 (deg)")
        ax.set_title(label)
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--paraflex", help="binary (default: paraflex_tools.runner's)")
    ap.add_argument("--work", type=Path, default=Path("/tmp/robot_static_map"))
    args = ap.parse_args()
    binary = find_binary(args.paraflex)
    runs = {v: build(v, args.work, binary) for v in ("pfmb", "fmb", "fmb40")}
    p = runs["pfmb"]["poses"]
    axes_deg = [np.degrees(p.axis(d)) for d in p.drives]
    values = maps(p)
    img = REPO / "docs" / "img"
    draw(values, axes_deg, "Robolink pFMB, static equilibrium under gravity over M2, M3",
         img / "robot_map_values.png", percent=False)
    summary = {"provenance": PROVENANCE, "binary": str(binary), "deck":
               "decks/robot/fmb/robot_grid.dat", "grid": list(p.shape),
               "converged": {v: int(r["poses"].converged.sum()) for v, r in runs.items()},
               "artifact_build_s": {v: round(r["build_s"], 2) for v, r in runs.items()},
               "grid_solve_s": {v: r["grid_s"] for v, r in runs.items()},
               "newton": {v: r["newton"] for v, r in runs.items()},
               "pfmb_range": {k: [float(np.nanmin(m)), float(np.nanmax(m))]
                              for k, m in values.items()},
               "max_error": {}}
    for ref in ("fmb", "fmb40"):
        r = maps(runs[ref]["poses"])
        err = {k: np.abs(values[k] - r[k]) / np.nanmax(np.abs(r[k])) for k in SENSORS}
        summary["max_error"][ref] = {k: float(np.nanmax(e)) for k, e in err.items()}
        what = ("ROMs at the reference parameters" if ref == "fmb"
                else "ROMs with 40 modes per body")
        draw(err, axes_deg, f"pFMB vs FMB ({what}): |y_pFMB − y_FMB| / max |y_FMB|",
             img / f"robot_map_error_{ref}.png", percent=True)
    out = REPO / "reference" / "robot" / "static_map.json"
    out.write_text(json.dumps(summary, indent=1) + "\n")
    print(json.dumps(summary, indent=1))


if __name__ == "__main__":
    main()
