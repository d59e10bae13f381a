"""Fixtures shared by the tools tests."""
import os
from pathlib import Path

import pytest

from paraflex_tools import REPO


@pytest.fixture(scope="session")
def paraflex_binary() -> Path:
    """A built paraflex binary for tests that run the solver: ``$PARAFLEX``, else the newer of
    the release and debug builds of ``$CARGO_TARGET_DIR`` or of this checkout (``make test``
    builds the debug one with ``cargo test`` before it runs these tests; an older release build
    left from an earlier checkout must not be the one tested). Missing, the test fails and says
    how to build it: a test that skips itself would pass without checking anything."""
    if os.environ.get("PARAFLEX"):
        path = Path(os.environ["PARAFLEX"])
        if path.is_file():
            return path.resolve()
        pytest.fail(f"$PARAFLEX is {path}: no such file")
    target = Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))
    candidates = [target / "release" / "paraflex", target / "debug" / "paraflex"]
    built = [path for path in candidates if path.is_file()]
    if built:
        return max(built, key=lambda path: path.stat().st_mtime).resolve()
    pytest.fail(f"no paraflex binary among {', '.join(map(str, candidates))}: run `cargo build` first")
