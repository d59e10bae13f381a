"""Running the paraflex binary: where it is, and ``paraflex run DECK -o OUT`` with its exit
code, console output and wall time.

The binary is, in this order: the path given by the caller, ``$PARAFLEX``, the release build
``$CARGO_TARGET_DIR/release/paraflex`` when ``CARGO_TARGET_DIR`` is set, else the release
build of the checkout this package lives in (``<repository>/target/release/paraflex``).
"""
from __future__ import annotations

import os
import shutil
import subprocess
import time
from dataclasses import dataclass
from pathlib import Path

from paraflex_tools import REPO


def default_binary() -> Path:
    """The paraflex binary used when the caller names none (it may not be built yet)."""
    if os.environ.get("PARAFLEX"):
        return Path(os.environ["PARAFLEX"])
    target = os.environ.get("CARGO_TARGET_DIR")
    if target:
        return Path(target) / "release" / "paraflex"
    build = REPO / "target" / "release" / "paraflex"
    on_path = shutil.which("paraflex")
    return Path(on_path) if on_path and not build.is_file() else build


def find_binary(binary: str | os.PathLike | None = None) -> Path:
    """``binary``, or :func:`default_binary`; an error naming the path when it does not exist."""
    path = Path(binary) if binary else default_binary()
    if not path.is_file():
        raise FileNotFoundError(f"no paraflex binary at {path} (build it with `cargo build --release`, "
                                "or name one with --paraflex / $PARAFLEX)")
    return path


@dataclass
class Run:
    """One finished paraflex process."""

    command: list[str]
    returncode: int
    stdout: str
    stderr: str
    seconds: float

    @property
    def ok(self) -> bool:
        return self.returncode == 0


class RunFailed(SystemExit):
    """A paraflex run that had to succeed exited non-zero; the message carries its output."""


def run(deck: str | os.PathLike, output: str | os.PathLike, binary: str | os.PathLike | None = None, *,
        cwd: str | os.PathLike | None = None, timeout: float | None = None) -> Run:
    """``paraflex run deck -o output``, console output captured; never raises on a failed run
    (a timeout raises :class:`subprocess.TimeoutExpired`)."""
    command = [str(find_binary(binary)), "run", str(deck), "-o", str(output)]
    start = time.perf_counter()
    p = subprocess.run(command, capture_output=True, text=True, cwd=cwd, timeout=timeout)
    return Run(command, p.returncode, p.stdout, p.stderr, time.perf_counter() - start)


def run_checked(deck: str | os.PathLike, output: str | os.PathLike, binary: str | os.PathLike | None = None,
                **kwargs) -> Run:
    """:func:`run`, raising :class:`RunFailed` (its stdout and stderr in the message) on a
    non-zero exit code."""
    r = run(deck, output, binary, **kwargs)
    if not r.ok:
        raise RunFailed(f"paraflex failed on {deck} (exit code {r.returncode}):\n{r.stdout}{r.stderr}")
    return r
