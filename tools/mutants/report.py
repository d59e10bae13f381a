#!/usr/bin/env python3
"""Write docs/mutation-testing.md from the cargo-mutants outcomes of tools/mutants/run.sh.

Reads mutants.out/<module>/mutants.out/outcomes.json for every module run (and
mutants.out/<module>-rerun-<time>/..., later runs of some of the module's mutants, whose outcomes
replace the earlier ones for the same mutants), the command and commit recorded beside them, and
tools/mutants/explained.toml, where each mutant the tests still miss is explained as equivalent.

Per module: mutants total / caught / missed / timeout / unviable and the caught ratio
(caught + timeout) / (caught + missed + timeout), i.e. among the mutants that compile; a timeout
(a test hangs on the mutant) is a detection, and the report names the tests that had already
failed by then. Every
mutant missed by the first run is listed with the tests that catch it now (read from the rerun's
log: the new tests) or with its equivalence argument; one that is neither is flagged
"UNEXPLAINED", and the script exits with status 1 so that the habit cannot silently lapse.
"""

from __future__ import annotations

import argparse
import json
import re
import sys
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

OUTCOMES = ("CaughtMutant", "MissedMutant", "Timeout", "Unviable")
LABELS = {"CaughtMutant": "caught", "MissedMutant": "missed", "Timeout": "timeout", "Unviable": "unviable"}


@dataclass
class Run:
    """One cargo-mutants run: its command, commit, version and per-mutant outcomes."""

    directory: Path
    command: str
    commit: str
    version: str
    outcomes: dict[str, str]
    logs: dict[str, Path]
    planned: int
    finished: bool


@dataclass
class Module:
    """A source file's first run and its reruns, merged mutant by mutant (later runs win)."""

    file: str
    first: Run
    reruns: list[Run] = field(default_factory=list)

    def final(self) -> dict[str, str]:
        merged = dict(self.first.outcomes)
        for run in self.reruns:
            merged.update(run.outcomes)
        return merged

    def killed_later(self) -> dict[str, Path]:
        """Mutants a run missed and a later run caught, with the log of the run that caught them."""
        runs = [self.first, *self.reruns]
        killed = {}
        for i, run in enumerate(runs):
            for name, outcome in run.outcomes.items():
                if outcome != "MissedMutant":
                    continue
                later = [r for r in runs[i + 1 :] if name in r.outcomes]
                if later and later[-1].outcomes[name] == "CaughtMutant":
                    killed[name] = later[-1].logs[name]
        return killed

    def counts(self) -> dict[str, int]:
        final = self.final()
        return {o: sum(1 for v in final.values() if v == o) for o in OUTCOMES}


def read_run(directory: Path) -> Run | None:
    """The run recorded in `directory` (run.sh's output for one module), if it finished."""
    out = directory / "mutants.out"
    path = out / "outcomes.json"
    if not path.exists():
        return None
    data = json.loads(path.read_text())
    outcomes, logs = {}, {}
    for o in data["outcomes"]:
        scenario = o["scenario"]
        if not isinstance(scenario, dict) or "Mutant" not in scenario:
            continue
        name = scenario["Mutant"]["name"]
        outcomes[name] = o["summary"]
        logs[name] = out / o["log_path"]

    def text(name: str) -> str:
        p = directory / name
        return p.read_text().strip() if p.exists() else "(not recorded)"

    planned = len(json.loads((out / "mutants.json").read_text()))
    finished = data.get("end_time") is not None
    return Run(
        directory, text("command.txt"), text("commit.txt"), data["cargo_mutants_version"], outcomes, logs,
        planned, finished,
    )


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


def file_of(run: Run) -> str:
    """The source file a run mutated, from the names of its mutants or its command."""
    for name in run.outcomes:
        return name.split(":", 1)[0]
    m = re.search(r"--file (\S+)", run.command)
    return m.group(1) if m else run.directory.name


def load_modules(root: Path) -> list[Module]:
    modules: dict[str, Module] = {}
    directories = sorted(p for p in root.iterdir() if p.is_dir()) if root.exists() else []
    for d in directories:
        if "-rerun-" in d.name:
            continue
        run = read_run(d)
        if run is not None:
            modules[d.name] = Module(file_of(run), run)
    for d in directories:  # sorted: reruns in time order
        base = d.name.split("-rerun-", 1)[0]
        if "-rerun-" in d.name and base in modules:
            run = read_run(d)
            if run is not None:
                modules[base].reruns.append(run)
    return list(modules.values())


def load_explanations(path: Path) -> dict[str, str]:
    if not path.exists():
        return {}
    data = tomllib.loads(path.read_text())
    return {m["name"]: m["equivalent"] for m in data.get("mutant", [])}


def ratio(counts: dict[str, int]) -> str:
    viable = counts["CaughtMutant"] + counts["MissedMutant"] + counts["Timeout"]
    detected = counts["CaughtMutant"] + counts["Timeout"]
    return f"{100.0 * detected / viable:.1f} %" if viable else "—"


def failed_before_timeout(log: Path) -> list[str]:
    """Tests that cargo test had already reported FAILED when a hang stopped the run."""
    if not log.exists():
        return []
    return [
        line.split()[1]
        for line in log.read_text(errors="replace").splitlines()
        if line.startswith("test ") and line.rstrip().endswith("... FAILED")
    ]


def split_name(name: str) -> tuple[str, str]:
    """`file:line:col: description` → (`line:col`, description)."""
    if ": " not in name:
        return "", name
    place, what = name.split(": ", 1)
    return place.split(":", 1)[1], what


def render(modules: list[Module], explanations: dict[str, str], order: list[str]) -> tuple[str, int]:
    """The page's generated part, and the number of unexplained missed mutants."""
    rank = {f: i for i, f in enumerate(order)}
    modules = sorted(modules, key=lambda m: (rank.get(m.file, len(rank)), m.file))
    lines = [
        "| module | mutants tested | caught | missed | timeout | unviable | caught ratio | missed before the new tests |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for m in modules:
        c, final = m.counts(), m.final()
        tested = f"{len(final)}" if len(final) >= m.first.planned else f"{len(final)} of {m.first.planned}"
        lines.append(
            f"| `{m.file}` | {tested} | {c['CaughtMutant']} | {c['MissedMutant']} | {c['Timeout']} "
            f"| {c['Unviable']} | {ratio(c)} | {len(m.killed_later())} |"
        )
    for file in order:
        if file not in {m.file for m in modules}:
            lines.append(f"| `{file}` | not run yet | | | | | | |")
    unexplained = 0
    for m in modules:
        lines += ["", f"### `{m.file}`", ""]
        for label, run in [("Run", m.first)] + [("Rerun", r) for r in m.reruns]:
            done = "" if run.finished else f", stopped after {len(run.outcomes)} of its {run.planned} mutants"
            lines.append(f"{label} at commit {run.commit} (cargo-mutants {run.version}{done}):")
            lines += ["", "```sh", run.command, "```", ""]
        final = m.final()
        if len(final) < m.first.planned:
            lines += [f"{m.first.planned - len(final)} mutants of the file were not tested (the run was stopped).", ""]
        killed = m.killed_later()
        missed = [n for n, o in final.items() if o == "MissedMutant"]
        timeouts = [n for n, o in final.items() if o == "Timeout"]
        if not killed and not missed and not timeouts:
            lines.append("Every viable mutant tested was caught.")
        for name, log in killed.items():
            where, what = split_name(name)
            tests = failing_tests(log)
            killers = ", ".join(f"`{t}`" for t in tests[:4]) if tests else "the rerun's tests"
            if len(tests) > 4:
                killers += f" and {len(tests) - 4} more"
            lines.append(f"- {where} `{what}`: missed, now killed by {killers}")
        for name in missed:
            where, what = split_name(name)
            if name in explanations:
                lines.append(f"- {where} `{what}`: equivalent: {explanations[name]}")
            else:
                unexplained += 1
                lines.append(f"- {where} `{what}`: **UNEXPLAINED** (missed, no new test, no equivalence)")
        for name in timeouts:
            where, what = split_name(name)
            log = next(r.logs[name] for r in reversed([m.first, *m.reruns]) if name in r.logs)
            failed = failed_before_timeout(log)
            also = f"; before that, failed: {', '.join(f'`{t}`' for t in failed)}" if failed else ""
            lines.append(f"- {where} `{what}`: timeout (a test hangs on it){also}")
    stale = sorted(set(explanations) - {n for m in modules for n, o in m.final().items() if o == "MissedMutant"})
    if stale:
        lines += ["", "Explanations in `tools/mutants/explained.toml` that match no missed mutant any more "
                  "(the code moved or a test catches it now; re-check them): " + ", ".join(f"`{s}`" for s in stale)]
    return "\n".join(lines) + "\n", unexplained


BEGIN, END = "<!-- mutants report: begin (tools/mutants/report.py) -->", "<!-- mutants report: end -->"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out-dir", type=Path, default=Path("mutants.out"))
    parser.add_argument("--explained", type=Path, default=Path("tools/mutants/explained.toml"))
    parser.add_argument("--doc", type=Path, default=Path("docs/mutation-testing.md"))
    parser.add_argument("files", nargs="*", help="the order of the modules in the table (MUTANTS_FILES)")
    args = parser.parse_args()
    modules = load_modules(args.out_dir)
    if not modules:
        print(f"no finished cargo-mutants run under {args.out_dir}", file=sys.stderr)
        return 1
    body, unexplained = render(modules, load_explanations(args.explained), args.files)
    page = args.doc.read_text()
    if BEGIN not in page or END not in page:
        print(f"{args.doc} lacks the markers {BEGIN} … {END}", file=sys.stderr)
        return 1
    head, rest = page.split(BEGIN, 1)
    tail = rest.split(END, 1)[1]
    args.doc.write_text(f"{head}{BEGIN}\n{body}{END}{tail}")
    print(f"wrote {args.doc}: {len(modules)} module(s), {unexplained} unexplained missed mutant(s)")
    return 1 if unexplained else 0


if __name__ == "__main__":
    sys.exit(main())
