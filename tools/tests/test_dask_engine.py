"""The Dask engine (``paraflex run --engine``) against the study's own threads."""
import json
import shutil
import subprocess
import sys

import h5py
import numpy as np

from paraflex_tools import REPO

# A spinning strip (decks/fmb/strip_spin.dat, first 40 ms) whose density is the design
# variable: two generations of four designs, so that the engine serves two batches.
STUDY = """SOL OPTIMIZE
CEND
TSTEP = 1
BEGIN BULK
TSTEP,1,40,1.e-3,1
TINTEG,1,BDF2
FLEXB,1,STRIP,'strip_body.h5'
MARKER,10,1,14
MARKER,11,1,26
JOINT,1,REV,10,0,0.,0.,1.
JDRIVE,1,1,7,1.
TABLEF,7,'strip_spin_drive.csv',time,angle
MSENSOR,1,TIPDEV,DEV,,11
MSENSOR,2,WORK,ENERGY,,1
DESVAR,1,RHO,2700.,2000.,3400.
DVMAP,1,1,STRIP.RHO
DOBJ,1,DEV,MIN,TIPDEV,MAX
DOBJ,2,ENERGY,MIN,WORK,FINAL
MOOPT,1,NSGA2,8,4,1,2
ENDDATA
"""


def _run(paraflex, deck, out, *extra):
    run = subprocess.run(
        [str(paraflex), "run", str(deck), "-o", str(out), *extra],
        capture_output=True,
        text=True,
        check=False,
    )
    assert run.returncode == 0, run.stderr
    return run


def _study(path):
    with h5py.File(path, "r") as f:
        g = f["results/1/optimize"]
        return g["designs"][()], g["responses"][()]


def test_a_dask_study_equals_the_threaded_study_bit_for_bit(paraflex_binary, tmp_path):
    shutil.copy(REPO / "decks/fmb/strip_spin_drive.csv", tmp_path)
    built = subprocess.run(
        [str(paraflex_binary), "run", str(REPO / "decks/fmb/strip_body_prom.dat"),
         "-o", str(tmp_path / "strip_body.h5")],
        capture_output=True, text=True, check=False,
    )
    assert built.returncode == 0, built.stderr
    deck = tmp_path / "study.dat"
    deck.write_text(STUDY)
    _run(paraflex_binary, deck, tmp_path / "threads.h5")
    engine = f"{sys.executable} -m paraflex_tools.dask_engine --local 2"
    run = _run(paraflex_binary, deck, tmp_path / "dask.h5", "--engine", engine)
    assert "dask_engine --local 2" in run.stdout, run.stdout
    designs_t, responses_t = _study(tmp_path / "threads.h5")
    designs_d, responses_d = _study(tmp_path / "dask.h5")
    assert designs_t.shape == (8, 1) and responses_t.shape == (8, 2)
    # the same designs proposed, and each evaluated to the same bits in a worker process
    np.testing.assert_array_equal(designs_d.view(np.uint64), designs_t.view(np.uint64))
    np.testing.assert_array_equal(responses_d.view(np.uint64), responses_t.view(np.uint64))
    # every evaluation journaled as it came back
    journal = (tmp_path / "dask.h5.designs-1.jsonl").read_text().splitlines()
    assert len(journal) == 1 + 8


def test_a_failing_worker_fails_its_designs_with_the_reason(paraflex_binary, tmp_path):
    from paraflex_tools.dask_engine import evaluate_chunk

    deck = tmp_path / "study.dat"
    deck.write_text(STUDY)  # its drive table and artifact are missing: paraflex evaluate fails
    lines = evaluate_chunk(str(paraflex_binary), str(deck), 1, [[2500.0], [3000.0]])
    answers = [json.loads(line) for line in lines]
    assert [a["design"] for a in answers] == [[2500.0], [3000.0]]
    for a in answers:
        assert a["responses"] is None
        assert "Dask worker failed" in a["error"] and "No such file" in a["error"], a
