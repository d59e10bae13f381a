"""tools/compare_outputs.py end to end, with stand-in binaries that write a small HDF5 file."""
import stat
import subprocess
import sys
from pathlib import Path

import pytest

SCRIPT = Path(__file__).resolve().parents[1] / "compare_outputs.py"
DECK = "demo/bracket_plate"  # one small deck of decks/

FAKE = """#!{python}
import sys, h5py, numpy as np
out = sys.argv[sys.argv.index("-o") + 1]
with h5py.File(out, "w") as f:
    f.attrs["paraflex_version"] = "{version}"
    g = f.create_group("results/1/modal")
    g["frequency_hz"] = np.array([1.0, {f2!r}])
    g.attrs["method"] = "{method}"
    f["prom/build/timings"] = np.array([{seconds!r}])
sys.exit({code})
"""


def fake(tmp_path: Path, name: str, version="1", f2=2.0, method="lanczos", seconds=1.0, code=0) -> Path:
    path = tmp_path / name
    path.write_text(FAKE.format(python=sys.executable, version=version, f2=f2, method=method,
                                seconds=seconds, code=code))
    path.chmod(path.stat().st_mode | stat.S_IXUSR)
    return path


def compare(before: Path, after: Path) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, str(SCRIPT), "--before", str(before), "--after", str(after),
                           "--filter", DECK], capture_output=True, text=True)


def test_version_and_timings_are_ignored_and_tiny_differences_pass(tmp_path):
    r = compare(fake(tmp_path, "a"), fake(tmp_path, "b", version="2", seconds=9.0, f2=2.0 * (1 + 4e-13)))
    assert r.returncode == 0, r.stdout + r.stderr
    assert "OK " in r.stdout and r.stdout.rstrip().endswith("1 passed, 0 failed")


@pytest.mark.parametrize("change, shown", [
    (dict(f2=2.0 * (1 + 1e-9)), "/results/1/modal/frequency_hz relative difference 1.000e-09"),
    (dict(method="subspace"), "/results/1/modal@method"),
])
def test_a_different_number_or_string_is_a_diff(tmp_path, change, shown):
    r = compare(fake(tmp_path, "a"), fake(tmp_path, "b", **change))
    assert r.returncode == 1
    assert "DIFF" in r.stdout and shown in r.stdout, r.stdout
    assert r.stdout.rstrip().endswith("0 passed, 1 failed")


def test_a_different_exit_code_is_a_failure(tmp_path):
    r = compare(fake(tmp_path, "a"), fake(tmp_path, "b", code=3))
    assert r.returncode == 1 and "FAILED" in r.stdout and "exit code 0 before, 3 after" in r.stdout
