#!/usr/bin/env python3
"""Run every deck in decks/ with two paraflex binaries and compare what they write.

    .venv/bin/python tools/compare_outputs.py --before OLD_BIN [--after NEW_BIN] [--jobs 2]
        [--filter REGEX] [--timeout SECONDS] [--skip-xdmf]

A deck is a file under decks/ (not decks/bad/, whose decks must fail) with a ``SOL`` line
and a ``BEGIN BULK`` line; files without them are includes. A deck that includes meshes/full/
is a full-size variant whose mesh is not committed (made on demand by ``make meshes-full``) and
is skipped, as tests/scenes.rs does.

Each binary runs ``paraflex run <deck> -o out.h5`` in its own temporary directory. The two runs
of a deck must give the same exit code and write the same set of files; every HDF5 file must
hold the same groups, datasets and attributes, numbers equal to 1e-12 relative
(|a - b| <= 1e-12 max(|a|, |b|, tiny), tiny the smallest normal double; NaN equals NaN) and
strings exactly; other files must be byte-identical. The temporary directory's path is replaced
by a placeholder before strings are compared. Ignored: the keys in IGNORED_ATTRIBUTES and
IGNORED_DATASETS (wall-clock timings and the version string).

One line per deck: OK, DIFF (the worst dataset or attribute and its relative difference) or
FAILED (a timeout, different exit codes or different sets of written files), with each
binary's wall time; then ``N passed, N failed``. The exit code is 1 when any deck is not OK.
"""
from __future__ import annotations

import argparse
import concurrent.futures
import re
import subprocess
import sys
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

import h5py
import numpy as np

from paraflex_tools import runner
from paraflex_tools.results import walk

DECKS = runner.REPO / "decks"
RTOL = 1e-12
TINY = np.finfo(np.float64).tiny
TEMP_PLACEHOLDER = "<output directory>"

# attribute name -> why it differs between two runs of the same binary
IGNORED_ATTRIBUTES = {
    "paraflex_version": "version string of the binary",
    "steps_per_second": "wall-clock speed of SOL ESTIMATE's filter loop",
}
# dataset path -> why
IGNORED_DATASETS = {
    "/prom/build/timings": "wall-clock seconds of each pROM build phase",
}


def decks(pattern: str | None) -> list[Path]:
    """The runnable decks under decks/, sorted, whose path relative to decks/ matches ``pattern``."""
    found = []
    for path in sorted(DECKS.rglob("*")):
        rel = path.relative_to(DECKS).as_posix()
        if not path.is_file() or path.suffix not in (".dat", ".bdf") or rel.startswith("bad/"):
            continue
        text = path.read_text(errors="replace")
        if not (re.search(r"(?im)^\s*SOL\s", text) and re.search(r"(?im)^\s*BEGIN\s+BULK", text)):
            continue
        if "meshes/full/" in text or (pattern and not re.search(pattern, rel)):
            continue
        found.append(path)
    return found


@dataclass
class Output:
    """What one binary did with one deck."""

    returncode: int | None  # None: timed out
    seconds: float
    files: dict[str, bytes | dict] = field(default_factory=dict)  # relative path -> bytes, or HDF5 entries


def run_one(binary: Path, deck: Path, timeout: float | None, skip_xdmf: bool = False) -> Output:
    with tempfile.TemporaryDirectory(prefix="compare_outputs_") as tmp:
        try:
            r = runner.run(deck, "out.h5", binary, cwd=tmp, timeout=timeout)
        except subprocess.TimeoutExpired:
            return Output(None, float(timeout or 0))
        out = Output(r.returncode, r.seconds)
        for path in sorted(Path(tmp).rglob("*")):
            if path.is_file() and not (skip_xdmf and path.suffix == ".xdmf"):
                rel = path.relative_to(tmp).as_posix()
                out.files[rel] = read_hdf5(path, tmp) if path.suffix == ".h5" else path.read_bytes().replace(
                    tmp.encode(), TEMP_PLACEHOLDER.encode())
        return out


def read_hdf5(path: Path, tmp: str) -> dict | bytes:
    """{path or path@attribute: value} of every entry but the ignored ones; the file's bytes
    when HDF5 cannot read it."""
    entries = {}
    try:
        with h5py.File(path, "r") as f:
            for key, kind, value in walk(f):
                if kind == "attribute" and key.rsplit("@", 1)[1] in IGNORED_ATTRIBUTES:
                    continue
                if kind == "dataset" and key in IGNORED_DATASETS:
                    continue
                entries[key] = normalise(value, tmp)
    except OSError:
        return path.read_bytes()
    return entries


def normalise(value, tmp: str):
    """Strings decoded with the temporary directory replaced, string arrays as lists with their
    shape, an empty dataspace as its type, numbers as numpy arrays."""
    if value is None:
        return None
    if isinstance(value, h5py.Empty):
        return f"empty {value.dtype}"
    if isinstance(value, (bytes, str)):
        s = value.decode(errors="replace") if isinstance(value, bytes) else value
        return s.replace(tmp, TEMP_PLACEHOLDER)
    a = np.asarray(value)
    if a.dtype.kind in "OSU":
        items = [normalise(v, tmp) if isinstance(v, (bytes, str)) else repr(v) for v in a.ravel().tolist()]
        return items + [f"shape {a.shape}"]
    return a


def relative_difference(a, b) -> float:
    """0 when equal; the largest |a - b| / max(|a|, |b|, tiny) over the entries of numeric
    arrays (NaN against NaN counts as equal); inf when shapes, types or strings differ."""
    if isinstance(a, np.ndarray) and isinstance(b, np.ndarray):
        if a.shape != b.shape or a.dtype.names != b.dtype.names:
            return float("inf")
        if a.dtype.names:
            return max((relative_difference(a[n], b[n]) for n in a.dtype.names), default=0.0)
        if a.dtype.kind not in "biufc" or b.dtype.kind not in "biufc":
            return 0.0 if np.array_equal(a, b) else float("inf")
        if np.array_equal(a, b):
            return 0.0
        common = np.complex128 if "c" in a.dtype.kind + b.dtype.kind else np.float64
        a, b = a.astype(common), b.astype(common)
        with np.errstate(invalid="ignore"):
            same = (a == b) | (np.isnan(a) & np.isnan(b))
            diff = np.where(same, 0.0, np.abs(a - b) / np.maximum(np.maximum(np.abs(a), np.abs(b)), TINY))
        diff = np.where(np.isnan(diff), np.inf, diff)
        return float(diff.max()) if diff.size else 0.0
    return 0.0 if type(a) is type(b) and a == b else float("inf")


def compare(before: Output, after: Output) -> tuple[str, str]:
    """(status, detail) of one deck."""
    if before.returncode is None or after.returncode is None:
        which = " and ".join(n for n, o in (("before", before), ("after", after)) if o.returncode is None)
        return "FAILED", f"timed out ({which})"
    if before.returncode != after.returncode:
        return "FAILED", f"exit code {before.returncode} before, {after.returncode} after"
    if set(before.files) != set(after.files):
        return "FAILED", f"files written: {sorted(before.files)} before, {sorted(after.files)} after"
    worst, worst_key, count = 0.0, "", 0
    for name in sorted(before.files):
        a, b = before.files[name], after.files[name]
        if isinstance(a, bytes):
            pairs = [(name, a, b)]
        else:
            keys = set(a) | set(b)
            pairs = [(f"{name}:{k}", a.get(k, "<absent>"), b.get(k, "<absent>")) for k in sorted(keys)]
        for key, x, y in pairs:
            d = relative_difference(x, y)
            if d > RTOL:
                count += 1
                if d > worst or not worst_key:
                    worst, worst_key = d, key
    code = f"exit {before.returncode}"
    if count:
        return "DIFF", f"{code}; {count} entries differ, worst {worst_key} relative difference {worst:.3e}"
    return "OK", code


def check_deck(deck: Path, args) -> tuple[str, str]:
    before = run_one(args.before, deck, args.timeout, args.skip_xdmf)
    after = run_one(args.after, deck, args.timeout, args.skip_xdmf)
    status, detail = compare(before, after)
    rel = deck.relative_to(DECKS).as_posix()
    line = f"{status:<6} {rel:<52} before {before.seconds:8.2f} s  after {after.seconds:8.2f} s  {detail}"
    return status, line


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--before", type=Path, required=True, help="the paraflex binary before the change")
    ap.add_argument("--after", type=Path, default=runner.default_binary(),
                    help="the paraflex binary after the change (default: %(default)s)")
    ap.add_argument("--jobs", type=int, default=1, help="decks run at the same time (default 1)")
    ap.add_argument("--filter", metavar="REGEX", help="only decks whose path under decks/ matches")
    ap.add_argument("--timeout", type=float, default=1800.0, help="seconds per run (default %(default)g)")
    ap.add_argument("--skip-xdmf", action="store_true",
                    help="leave the XDMF files out (to compare across a change of the XDMF layout)")
    args = ap.parse_args(argv)
    args.before, args.after = runner.find_binary(args.before), runner.find_binary(args.after)
    todo = decks(args.filter)
    if not todo:
        ap.error("no deck matches")
    print(f"{len(todo)} decks; before {args.before}, after {args.after}", flush=True)
    passed = failed = 0
    with concurrent.futures.ThreadPoolExecutor(max_workers=max(1, args.jobs)) as pool:
        for status, line in pool.map(lambda d: check_deck(d, args), todo):
            print(line, flush=True)
            passed, failed = (passed + 1, failed) if status == "OK" else (passed, failed + 1)
    print(f"{passed} passed, {failed} failed")
    return 0 if failed == 0 else 1


if __name__ == "__main__":
    sys.exit(main())
