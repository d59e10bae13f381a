# %% [markdown]
# # Post-processing paraflex results in Python
#
# A notebook-style script (cells marked `# %%`: VS Code, Spyder and `jupytext --to notebook`
# open it as a notebook; `python tools/examples/postprocess.py WORKDIR` runs it whole). It
# builds the small cantilever plate's pROM in E and RHO (`decks/estimate/plate_prom.dat`),
# then, with `paraflex_tools`:
#
# 1. evaluates the pROM at any parameter point in numpy (`paraflex_tools.prom.Prom`) and sweeps
#    E to see the frequencies move as √E;
# 2. reads an FRF the solver computed on the pROM (`results.read_frf`) and overlays the numpy
#    evaluation at the same point;
# 3. reads the histories of a multibody run (`results.read_multibody`).
#
# Every figure is written as a PNG into WORKDIR. The binary is found as `paraflex_tools.runner`
# documents (`$PARAFLEX`, else the checkout's release build).

# %%
import shutil
import sys
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from paraflex_tools import REPO, prom, results, runner  # noqa: E402

work = Path(sys.argv[1] if len(sys.argv) > 1 else "postprocess_example").resolve()
work.mkdir(parents=True, exist_ok=True)
for name in ("plate_prom.dat", "plate.bdf"):
    shutil.copy(REPO / "decks" / "estimate" / name, work / name)
runner.run_checked(work / "plate_prom.dat", work / "prom.h5", cwd=work)

# %% [markdown]
# ## 1. The pROM at any parameter point
# `Prom` reads the artifact's parameters, affine functions and reduced components once;
# `frequencies(values)` sums K_r(p), M_r(p) (thesis eq. 3.31–3.32) and solves the small
# eigenproblem. One material: every frequency scales as √E.

# %%
model = prom.Prom(work / "prom.h5")
print("parameters:", [(p.name, p.low, p.high, p.nominal) for p in model.parameters])
print("reduced size:", model.size, "sensors:", model.sensor_names, "inputs:", model.input_names)
moduli = np.linspace(model.parameters[0].low, model.parameters[0].high, 21)
sweep = np.array([model.frequencies({"E": e})[:3] for e in moduli])
fig, ax = plt.subplots(figsize=(6, 3.5))
ax.plot(moduli / 1e9, sweep, marker=".")
ax.set_xlabel("E [GPa]")
ax.set_ylabel("frequency [Hz]")
ax.set_title("plate pROM: first three modes against E")
fig.tight_layout()
fig.savefig(work / "frequencies_vs_E.png", dpi=120)

# %% [markdown]
# ## 2. An FRF from the solver, and the same FRF in numpy
# The solver evaluates the pROM at `PVAL` (SOL 111 with `ROM =`); `read_frf` returns H as a
# complex array (line × output × input) with the output and input names.

# %%
point = {"E": 2.7e11, "RHO": 4500.0}
deck = work / "frf.dat"
deck.write_text(
    "SOL 111\nCEND\nROM = 'prom.h5'\nPVAL = 1\nFREQUENCY = 5\nDLOAD = 7\nBEGIN BULK\n"
    f"PVAL,1,E,{point['E']!r},RHO,{point['RHO']!r}\nFREQ1,5,10.,5.,200\n"
    "RLOAD1,7,8,,,20\nDAREA,8,14,3,1.\nTABLED1,20\n,0.,1.,5000.,1.,ENDT\nENDDATA\n"
)
runner.run_checked(deck, work / "frf.h5", cwd=work)
frf = results.read_frf(work / "frf.h5")
mine = model.frf(frf.frequency_hz, point)[:, model.sensor_names.index("D_TIP_A"), 0]
fig, ax = plt.subplots(figsize=(6, 3.5))
ax.semilogy(frf.frequency_hz, np.abs(frf.pair("D_TIP_A", "14:3")), label="paraflex SOL 111 (ROM =)")
ax.semilogy(frf.frequency_hz, np.abs(mine), "--", label="paraflex_tools.prom")
ax.set_xlabel("frequency [Hz]")
ax.set_ylabel("|H| D_TIP_A / 14:3 [m/N]")
ax.legend()
fig.tight_layout()
fig.savefig(work / "frf.png", dpi=120)
print("largest FRF difference (relative):", np.abs(mine - frf.pair("D_TIP_A", "14:3")).max() / np.abs(mine).max())

# %% [markdown]
# ## 3. A multibody run
# `read_multibody` gives the MSENSOR histories by name, the drives, the constraint residual and
# the Newton iterations of each step, and the run's attributes.

# %%
pendulum = (REPO / "decks" / "fmb" / "pendulum_rigid.dat").read_text().replace("TSTEP,1,2500,", "TSTEP,1,1000,")
(work / "pendulum.dat").write_text(pendulum)
runner.run_checked(work / "pendulum.dat", work / "pendulum.h5", cwd=work)
fmb = results.read_multibody(work / "pendulum.h5")
print("method:", fmb.attrs["method"], "sensors:", sorted(fmb.sensors))
fig, ax = plt.subplots(figsize=(6, 3.5))
ax.plot(fmb.time, fmb.sensors["KE"], label="kinetic energy [J]")
ax.plot(fmb.time, -9.81 * fmb.sensors["YCM"], label="potential energy drop m g Δy [J]")
ax.set_xlabel("time [s]")
ax.legend()
fig.tight_layout()
fig.savefig(work / "pendulum_energy.png", dpi=120)
