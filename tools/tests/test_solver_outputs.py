"""The result readers and the pROM evaluator on files the solver writes (not hand-made ones):
the small cantilever plate of ``decks/estimate`` and the rigid pendulum of ``decks/fmb``."""
import shutil

import numpy as np
import pytest

from paraflex_tools import REPO, prom, results, runner

PLATE = REPO / "decks" / "estimate"
# A point inside the box that is no LHS sample of the two-sample build.
POINT = {"E": 2.7e11, "RHO": 4500.0}


def run(binary, directory, name, text):
    deck = directory / f"{name}.dat"
    deck.write_text(text)
    runner.run_checked(deck, directory / f"{name}.h5", binary, cwd=directory)
    return directory / f"{name}.h5"


@pytest.fixture(scope="module")
def plate(paraflex_binary, tmp_path_factory):
    """The plate's pROM in E and RHO (``plate_prom.dat``) built in a scratch directory."""
    directory = tmp_path_factory.mktemp("plate")
    for name in ("plate_prom.dat", "plate.bdf"):
        shutil.copy(PLATE / name, directory / name)
    runner.run_checked(directory / "plate_prom.dat", directory / "prom.h5", paraflex_binary, cwd=directory)
    return directory


def on_rom(body: str, sol: str) -> str:
    pval = ",".join(f"{k},{v!r}" for k, v in POINT.items())
    return f"SOL {sol}\nCEND\nROM = 'prom.h5'\nPVAL = 1\n{body[0]}BEGIN BULK\nPVAL,1,{pval}\n{body[1]}ENDDATA\n"


def test_prom_frequencies_match_the_solvers_evaluation(paraflex_binary, plate):
    # Both are a dense symmetric eigensolution of the same 7 × 7 K_r(p), M_r(p) in double
    # precision: they agree to round-off (1e-12 relative measured); 1e-9 leaves room for LAPACK
    # variants and is far below what a wrong f_i(p) causes (the second assertion: the nominal
    # point's frequencies differ from the evaluated point's by more than 1e-3).
    out = run(paraflex_binary, plate, "modes", on_rom(("METHOD = 1\n", "EIGRL,1,,,7\n"), "103"))
    solver = results.modal_frequencies(out)
    model = prom.Prom(plate / "prom.h5")
    np.testing.assert_allclose(model.frequencies(POINT), solver, rtol=1e-9)
    assert not np.allclose(model.frequencies(), solver, rtol=1e-3), "the point must move the modes"


def test_prom_frf_matches_the_solvers_pair_by_pair(paraflex_binary, plate):
    # The solver sums the Rayleigh-damped modes of K_r(p), M_r(p) (dynamics::frf::rayleigh_receptance),
    # this evaluator solves (K − ω²M + iωC) x = S_r: the same receptance in exact arithmetic for
    # symmetric K_r, M_r (the build symmetrizes them), so they agree to round-off; 1e-10 of the
    # largest |H| leaves room for the amplification near the 42 Hz resonance (Q ≈ 160) and is far
    # below a wrong f_i(p) or damping term (both move H by 1e-3 or more).
    dynamic = ("FREQUENCY = 5\nDLOAD = 7\n",
               "FREQ1,5,10.,50.,20\nRLOAD1,7,8,,,20\nDAREA,8,14,3,1.\nTABLED1,20\n,0.,1.,5000.,1.,ENDT\n")
    frf = results.read_frf(run(paraflex_binary, plate, "frf", on_rom(dynamic, "111")))
    model = prom.Prom(plate / "prom.h5")
    assert frf.params == POINT and frf.inputs == model.input_names == ["14:3"]
    H = model.frf(frf.frequency_hz, POINT)
    for s, name in enumerate(model.sensor_names):
        reference = frf.pair(name, "14:3")
        np.testing.assert_allclose(H[:, s, 0], reference, rtol=0, atol=1e-10 * np.abs(reference).max())


def test_prom_static_compliance_equals_the_full_models_statics(paraflex_binary, plate):
    # The basis holds the static mode K⁻¹ b of the tip input, and with one material K(E) = E K_E
    # keeps its direction for every E: the reduced static response S_rᵀ K_r⁻¹ S_r is the full
    # model's exactly (Galerkin on a space containing the solution), up to the round-off of the
    # two factorizations (1e-10 relative).
    out = run(paraflex_binary, plate, "static",
              "SOL 101\nCEND\nSPC = 1\nLOAD = 2\nBEGIN BULK\nFORCE,2,14,,1.,0.,0.,1.\nINCLUDE 'plate.bdf'\nENDDATA\n")
    statics = results.read_statics(out)
    model = prom.Prom(plate / "prom.h5")
    stiffness, _, _ = model.matrices({"E": 2.0e11})
    reduced = (model.input_shapes.T @ np.linalg.solve(stiffness, model.input_shapes))[0, 0]
    assert reduced == pytest.approx(statics.of_grid(14)[2], rel=1e-10)
    assert statics.displacement.shape == (len(statics.grid_ids), 6)


def test_prom_refuses_an_unknown_parameter(plate):
    with pytest.raises(KeyError, match="no parameter NU .*E, RHO"):
        prom.Prom(plate / "prom.h5").point({"NU": 0.3})


def test_multibody_histories_of_the_rigid_pendulum(paraflex_binary, tmp_path):
    # Released horizontal, undamped: BDF1 dissipates, so kinetic energy never exceeds the drop
    # m g Δy of the centre of mass (read through the reader's sensors); the reader must give
    # every history on the same time axis.
    deck = (REPO / "decks" / "fmb" / "pendulum_rigid.dat").read_text().replace("TSTEP,1,2500,", "TSTEP,1,300,")
    out = run(paraflex_binary, tmp_path, "pendulum", deck)
    fmb = results.read_multibody(out)
    assert fmb.attrs["method"] == "BDF1" and results.subcases(out) == ["1"]
    n = len(fmb.time)
    assert n == 61 and all(len(h) == n for h in fmb.sensors.values())
    assert len(fmb.constraint_residual) == n and len(fmb.newton_iterations) == n
    drop = 1.0 * 9.81 * (0.0 - fmb.sensors["YCM"])
    assert np.all(fmb.sensors["KE"] <= drop + 1e-9) and fmb.sensors["KE"][-1] > 0.1


def test_the_postprocessing_example_runs_and_agrees(paraflex_binary, tmp_path, monkeypatch, capsys):
    # The notebook-style example of docs/python.md, run as written: it must produce its three
    # figures, and its FRF overlay must be the solver's to round-off (printed by the example).
    import runpy

    monkeypatch.setenv("PARAFLEX", str(paraflex_binary))
    monkeypatch.setattr("sys.argv", ["postprocess.py", str(tmp_path)])
    runpy.run_path(str(REPO / "tools" / "examples" / "postprocess.py"), run_name="__main__")
    for png in ("frequencies_vs_E.png", "frf.png", "pendulum_energy.png"):
        assert (tmp_path / png).stat().st_size > 10_000
    difference = float(capsys.readouterr().out.split("largest FRF difference (relative):")[1].split()[0])
    assert difference < 1e-10


def test_exact_prom_response_is_the_limit_of_the_solvers_second_order_transient(paraflex_binary, plate):
    # Prom.response is exact for a load linear between samples; paraflex's generalized-α with
    # ρ∞ = 1 (the trapezoidal rule) is second order: its error against the exact response must
    # fall by 4 when Δt halves (measured 3.9 for D_TIP_A: 1.95e-3 at 0.1 ms, 5.0e-4 at 0.05 ms)
    # and be small at the finer step. [3.5, 4.5] admits the O(Δt³) remainder and nothing of
    # first order (a ratio of 2); a wrong hold, sign or sensor row gives no convergence at all.
    model = prom.Prom(plate / "prom.h5")
    fine_dt, steps = 2.5e-5, 8000
    table = np.arange(steps + 1) * fine_dt
    (plate / "sine.csv").write_text("time,force\n" + "".join(
        f"{t!r},{5.0 * np.sin(2 * np.pi * 20.0 * t)!r}\n" for t in table))
    errors = []
    for dt, n in ((1e-4, 2000), (5e-5, 4000)):
        dynamic = ("TSTEP = 1\nDLOAD = 7\n", f"TSTEP,1,{n},{dt!r},1\nTINTEG,1,GALPHA,1.\nTLOAD1,7,8,,,9\n"
                   "DAREA,8,14,3,1.\nTABLEF,9,'sine.csv',time,force\n")
        solver = results.read_transient(run(paraflex_binary, plate, f"tr{n}", on_rom(dynamic, "112")))
        exact = model.response(solver.time, np.interp(solver.time, table, 5.0 * np.sin(2 * np.pi * 20.0 * table))[:, None],
                               POINT)
        reference = solver.sensors["D_TIP_A"]
        errors.append(np.abs(exact[:, model.sensor_names.index("D_TIP_A")] - reference).max() / np.abs(reference).max())
    assert 3.5 < errors[0] / errors[1] < 4.5, errors
    assert errors[1] < 1e-3, errors


def test_simulated_measurements_are_the_exact_response_plus_seeded_noise(plate, tmp_path):
    # make_measurements.py --simulate: columns time, the sensors (sorted), the truth; without
    # noise the sensor columns are Prom.response at the truth point, with noise they differ by
    # the given σ (sample standard deviation of 2001 draws: within 10 %).
    import subprocess
    import sys

    (tmp_path / "load.csv").write_text("time,force\n0.0,0.0\n0.3,30.0\n")
    script = REPO / "tools" / "estimate" / "make_measurements.py"

    def make(name, *extra):
        subprocess.run([sys.executable, str(script), "--simulate", str(plate / "prom.h5"), "--load",
                        str(tmp_path / "load.csv"), "--dt", "1e-4", "--steps", "2000", "-o", str(tmp_path / name),
                        "--truth", "E=2.7e11", "--truth", "RHO=4500", "--seed", "3", *extra], check=True)
        return np.genfromtxt(tmp_path / name, delimiter=",", names=True)

    clean, noisy = make("clean.csv"), make("noisy.csv", "--sigma", "DISP=1e-7")
    model = prom.Prom(plate / "prom.h5")
    exact = model.response(clean["time"], 100.0 * clean["time"][:, None], POINT)
    assert list(clean.dtype.names) == ["time", *sorted(model.sensor_names), "E", "RHO"]
    for k, name in enumerate(model.sensor_names):
        np.testing.assert_allclose(clean[name], exact[:, k], rtol=1e-12, atol=1e-15)
    assert np.std(noisy["D_TIP_A"] - clean["D_TIP_A"]) == pytest.approx(1e-7, rel=0.1)
    np.testing.assert_array_equal(noisy["A_TIP"], clean["A_TIP"])
