"""Locating and running the paraflex binary."""
import stat
from pathlib import Path

import pytest

from paraflex_tools import runner


@pytest.fixture
def clean_env(monkeypatch):
    monkeypatch.delenv("PARAFLEX", raising=False)
    monkeypatch.delenv("CARGO_TARGET_DIR", raising=False)
    return monkeypatch


def fake_binary(path: Path, script: str) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text("#!/bin/sh\n" + script + "\n")
    path.chmod(path.stat().st_mode | stat.S_IXUSR)
    return path


def test_default_is_the_release_build_of_this_checkout(clean_env, tmp_path):
    clean_env.setenv("PATH", str(tmp_path))  # no paraflex on the PATH
    assert runner.default_binary() == runner.REPO / "target" / "release" / "paraflex"
    assert (runner.REPO / "Cargo.toml").is_file()


def test_cargo_target_dir_is_honoured(clean_env, tmp_path):
    clean_env.setenv("CARGO_TARGET_DIR", str(tmp_path / "t"))
    assert runner.default_binary() == tmp_path / "t" / "release" / "paraflex"


def test_paraflex_variable_comes_first(clean_env, tmp_path):
    clean_env.setenv("CARGO_TARGET_DIR", str(tmp_path / "t"))
    clean_env.setenv("PARAFLEX", str(tmp_path / "bin" / "pf"))
    assert runner.default_binary() == tmp_path / "bin" / "pf"


def test_missing_binary_is_named(clean_env, tmp_path):
    with pytest.raises(FileNotFoundError, match=str(tmp_path / "nothing")):
        runner.find_binary(tmp_path / "nothing")


def test_run_passes_deck_and_output_and_captures(tmp_path):
    exe = fake_binary(tmp_path / "paraflex", 'echo "$@"; echo oops >&2; exit 3')
    r = runner.run("deck.dat", "out.h5", exe, cwd=tmp_path)
    assert r.command == [str(exe), "run", "deck.dat", "-o", "out.h5"]
    assert (r.returncode, r.stdout, r.stderr, r.ok) == (3, "run deck.dat -o out.h5\n", "oops\n", False)
    assert r.seconds >= 0
    with pytest.raises(runner.RunFailed, match="exit code 3"):
        runner.run_checked("deck.dat", "out.h5", exe, cwd=tmp_path)
    assert runner.run_checked("d", "o", fake_binary(tmp_path / "good", "exit 0")).ok
