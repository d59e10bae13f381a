#!/usr/bin/env python3
"""Copy the outcomes of cargo-mutants runs into the repository's ledger, tools/mutants/ledger/.

tools/mutants/run.sh leaves each run in mutants.out/<module>[-rerun-<time>]/ (git-ignored: the
logs and mutated trees are large). This keeps what the report needs, one small JSON file per run,
so that docs/mutation-testing.md can be regenerated on any machine and a rerun can be merged with
an earlier run made elsewhere:

    {"file", "command", "commit", "cargo_mutants_version", "planned", "finished",
     "outcomes": {mutant name: CaughtMutant | MissedMutant | Timeout | Unviable},
     "offsets": {mutant name: [line − its function's first line, column]},
     "failing_tests": {mutant name: {"first": [test, ...], "total": n}},
     "sample": {"shard": "k/n", "file_mutants": m}}

`sample` is there only for a sampled run (run.sh's MUTANTS_SHARD: cargo-mutants' round-robin
shard k of n, every n-th mutant): `planned` then counts the shard's mutants and `file_mutants`
the whole file's.

`failing_tests` holds, for a rerun, the tests that caught each mutant an earlier run of the module
in the ledger had missed (a rerun is made after new tests, and the report names them), and for any
run, the tests that had failed before a timeout: the first `KEPT_TESTS` names and how many there
were.

    tools/mutants/record.py mutants.out/estimate-ekf [...]
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from pathlib import Path

KEPT_TESTS = 4


def failing_tests(log: Path) -> list[str]:
    """The test names cargo test lists under its closing `failures:` heading in a mutant's log."""
    if not log.exists():
        return []
    lines = log.read_text(errors="replace").splitlines()
    starts = [i for i, line in enumerate(lines) if line.strip() == "failures:"]
    if not starts:
        return []
    names = []
    for line in lines[starts[-1] + 1 :]:
        line = line.strip()
        if not line:
            break
        names.append(line)
    return names


def failed_before_timeout(log: Path) -> list[str]:
    """Tests that cargo test had already reported FAILED when a hang stopped the run."""
    if not log.exists():
        return []
    return [
        line.split()[1]
        for line in log.read_text(errors="replace").splitlines()
        if line.startswith("test ") and line.rstrip().endswith("... FAILED")
    ]


def mutant_key(name: str, offset: list[int]) -> tuple[str, int, int]:
    """A mutant's identity across runs at different commits.

    cargo-mutants names a mutant `file:line:col: description`, and code added above it moves the
    line; runs are matched by the description (which names the function) and the mutant's place
    relative to the start of its function, `offset` = [line − the function's first line, col]."""
    return (name.split(": ", 1)[-1], offset[0], offset[1])


def offset_in_function(mutant: dict) -> list[int]:
    """[line − the enclosing function's first line, column] of a cargo-mutants mutant."""
    start = mutant["span"]["start"]
    function = mutant.get("function") or {}
    first = function.get("span", {}).get("start", {}).get("line", 0)
    return [start["line"] - first, start["column"]]


def missed_earlier(ledger: Path, directory: Path) -> set[tuple[str, int, int]]:
    """Keys of the mutants that the ledger's earlier runs of `directory`'s module missed."""
    base = directory.name.split("-rerun-", 1)[0]
    missed = set()
    for path in sorted(ledger.glob(f"{base}*.json")):
        if path.stem >= directory.name or path.stem.split("-rerun-", 1)[0] != base:
            continue
        run = json.loads(path.read_text())
        missed |= {
            mutant_key(name, run["offsets"][name])
            for name, outcome in run["outcomes"].items()
            if outcome == "MissedMutant"
        }
    return missed


def read_run(directory: Path, ledger: Path) -> dict | None:
    """The ledger entry of the run that run.sh left in `directory`, or None if it has no outcomes."""
    out = directory / "mutants.out"
    path = out / "outcomes.json"
    if not path.exists():
        return None
    data = json.loads(path.read_text())
    earlier = missed_earlier(ledger, directory) if "-rerun-" in directory.name else set()
    outcomes, offsets, tests = {}, {}, {}
    for o in data["outcomes"]:
        scenario = o["scenario"]
        if not isinstance(scenario, dict) or "Mutant" not in scenario:
            continue
        name, summary = scenario["Mutant"]["name"], o["summary"]
        outcomes[name] = summary
        offsets[name] = offset_in_function(scenario["Mutant"])
        log = out / o["log_path"]
        if summary == "Timeout":
            tests[name] = failed_before_timeout(log)
        elif summary == "CaughtMutant" and mutant_key(name, offsets[name]) in earlier:
            tests[name] = failing_tests(log)

    def text(name: str) -> str:
        p = directory / name
        return p.read_text().strip() if p.exists() else "(not recorded)"

    command = text("command.txt")
    shard = re.search(r"--shard (\S+)", command)
    file = next(iter(outcomes), "").split(":", 1)[0]
    if not file:
        m = re.search(r"--file (\S+)", command)
        file = m.group(1) if m else directory.name
    entry = {
        "file": file,
        "command": command,
        "commit": text("commit.txt"),
        "cargo_mutants_version": data["cargo_mutants_version"],
        "planned": len(json.loads((out / "mutants.json").read_text())),
        "finished": data.get("end_time") is not None,
        "outcomes": outcomes,
        "offsets": offsets,
        "failing_tests": {k: {"first": v[:KEPT_TESTS], "total": len(v)} for k, v in tests.items() if v},
    }
    if shard:
        entry["sample"] = {"shard": shard.group(1), "file_mutants": int(text("file-mutants.txt"))}
    return entry


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("runs", nargs="+", type=Path, help="run directories under mutants.out/")
    parser.add_argument("--ledger", type=Path, default=Path("tools/mutants/ledger"))
    args = parser.parse_args()
    args.ledger.mkdir(parents=True, exist_ok=True)
    status = 0
    for directory in args.runs:
        entry = read_run(directory, args.ledger)
        if entry is None:
            print(f"{directory}: no outcomes.json (the run did not start testing)", file=sys.stderr)
            status = 1
            continue
        path = args.ledger / f"{directory.name}.json"
        if "-rerun-" not in directory.name:
            # a new first run supersedes the reruns of the one it replaces (they would sort after
            # it and override its newer outcomes); git keeps them
            for stale in args.ledger.glob(f"{directory.name}-rerun-*.json"):
                stale.unlink()
                print(f"removed {stale}: superseded by the new run")
        path.write_text(json.dumps(entry, indent=1, ensure_ascii=False, sort_keys=True) + "\n")
        print(f"recorded {path}: {len(entry['outcomes'])} of {entry['planned']} mutants")
    return status


if __name__ == "__main__":
    sys.exit(main())
