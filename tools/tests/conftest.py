"""Fixtures shared by the tools tests."""
import os
from pathlib import Path

import pytest

from paraflex_tools import REPO


@pytest.fixture(scope="session")
def paraflex_binary() -> Path:
    """A built paraflex binary for tests that run the solver: ``$PARAFLEX``, else the release or
    debug build of ``$CARGO_TARGET_DIR`` or of this checkout (``make test`` builds the debug one
    with ``cargo test`` before it runs these tests). Missing, the test fails and says how to build
    it: a test that skips itself would pass without checking anything."""
    candidates = [Path(os.environ["PARAFLEX"])] if os.environ.get("PARAFLEX") else []
    target = Path(os.environ.get("CARGO_TARGET_DIR", REPO / "target"))
    candidates += [target / "release" / "paraflex", target / "debug" / "paraflex"]
    for path in candidates:
        if path.is_file():
            return path.resolve()
    pytest.fail(f"no paraflex binary among {', '.join(map(str, candidates))}: run `cargo build` first")
