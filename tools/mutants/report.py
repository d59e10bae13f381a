#!/usr/bin/env python3
"""Write docs/mutation-testing.md from the mutation-testing ledger, tools/mutants/ledger/.

The ledger holds one JSON file per cargo-mutants run (tools/mutants/record.py writes it from the
git-ignored mutants.out/ that tools/mutants/run.sh fills): <module>.json for a module's first run,
<module>-rerun-<time>.json for later runs of some or all of its mutants, whose outcomes replace the
earlier ones for the same mutants (matched by `record.mutant_key`, so that a line moved by later
code still matches; a finished `--iterate` rerun tests every mutant not caught before, so a
missed mutant it did not test no longer exists), and tools/mutants/explained.toml, where each mutant the tests still miss is
explained as equivalent.

Per module: mutants total / caught / missed / timeout / unviable and the caught ratio
(caught + timeout) / (caught + missed + timeout), i.e. among the mutants that compile; a timeout
(a test hangs on the mutant) is a detection, and the report names the tests that had already
failed by then. Every mutant missed by an earlier run is listed with the tests that catch it now
(recorded from the rerun's log: the new tests) or with its equivalence argument; one that is
neither is flagged "UNEXPLAINED", and the script exits with status 1 so that the habit cannot
silently lapse.

A sampled module (tools/mutants/run.sh's MUTANTS_SHARD: cargo-mutants' round-robin shards) is
reported as such: the table counts the mutants tested, names the shards and the file's whole
mutant count, and its caught ratio is the sample's.
"""

from __future__ import annotations

import argparse
import json
import sys
import tomllib
from dataclasses import dataclass, field
from pathlib import Path

from record import mutant_key

OUTCOMES = ("CaughtMutant", "MissedMutant", "Timeout", "Unviable")


@dataclass
class Run:
    """One cargo-mutants run as the ledger keeps it."""

    name: str
    command: str
    commit: str
    version: str
    outcomes: dict[str, str]
    offsets: dict[str, list[int]]
    failing_tests: dict[str, dict]
    planned: int
    finished: bool
    sample: dict | None = None

    def keyed(self) -> dict[tuple[str, int, int], str]:
        """Mutant key → the mutant's name in this run."""
        return {mutant_key(name, self.offsets[name]): name for name in self.outcomes}

    def covers_the_uncaught(self) -> bool:
        """A finished `--iterate` run: it tested every mutant of the file not caught before."""
        return self.finished and "--iterate" in self.command


@dataclass
class Module:
    """A source file's first run and its reruns, merged mutant by mutant (later runs win)."""

    file: str
    first: Run
    reruns: list[Run] = field(default_factory=list)

    def runs(self) -> list[Run]:
        return [self.first, *self.reruns]

    def final(self) -> dict[tuple[str, int, int], tuple[str, str, Run]]:
        """Mutant key → (latest name, latest outcome, the run that gave it)."""
        merged = {}
        for run in self.runs():
            keyed = run.keyed()
            if run.covers_the_uncaught():
                merged = {k: v for k, v in merged.items() if v[1] == "CaughtMutant" or k in keyed}
            for k, name in keyed.items():
                merged[k] = (name, run.outcomes[name], run)
        return merged

    def killed_later(self) -> dict[tuple[str, int, int], tuple[str, dict]]:
        """Mutants a run missed and a later run caught: key → (name, that run's failing tests)."""
        runs = self.runs()
        killed = {}
        for i, run in enumerate(runs):
            for k, name in run.keyed().items():
                if run.outcomes[name] != "MissedMutant":
                    continue
                later = [(r, r.keyed()[k]) for r in runs[i + 1 :] if k in r.keyed()]
                if later and later[-1][0].outcomes[later[-1][1]] == "CaughtMutant":
                    r, latest = later[-1]
                    killed[k] = (latest, r.failing_tests.get(latest, {"first": [], "total": 0}))
        return killed

    def untested(self) -> int:
        """Mutants the latest run over the whole file (the first, or an `--iterate` rerun) did not
        reach because it was stopped; for a sample, those its shards' runs did not reach."""
        if self.first.sample:
            return sum(r.planned - len(r.outcomes) for r in self.runs() if r.sample)
        whole = [r for r in self.runs() if r is self.first or "--iterate" in r.command][-1]
        if whole is self.first:  # later partial runs may have reached some of them
            return max(0, whole.planned - len(self.final()))
        return whole.planned - len(whole.outcomes)

    def shards(self) -> dict[str, int]:
        """A sampled module's shards (`k/n`) → their mutant counts; empty for a whole file."""
        return {r.sample["shard"]: r.planned for r in self.runs() if r.sample} if self.first.sample else {}

    def unsampled(self) -> int:
        """Mutants of a sampled file in none of its shards (0 for a file run whole)."""
        if not self.first.sample:
            return 0
        return self.first.sample["file_mutants"] - sum(self.shards().values())

    def counts(self) -> dict[str, int]:
        final = self.final().values()
        return {o: sum(1 for _, v, _ in final if v == o) for o in OUTCOMES}


def read_run(path: Path) -> Run:
    d = json.loads(path.read_text())
    return Run(
        path.stem, d["command"], d["commit"], d["cargo_mutants_version"], d["outcomes"], d["offsets"], d["failing_tests"],
        d["planned"], d["finished"], d.get("sample"),
    )


def load_modules(ledger: Path) -> list[Module]:
    modules: dict[str, Module] = {}
    paths = sorted(ledger.glob("*.json")) if ledger.exists() else []
    for p in paths:
        if "-rerun-" not in p.stem:
            modules[p.stem] = Module(json.loads(p.read_text())["file"], read_run(p))
    for p in paths:  # sorted: reruns in time order
        base = p.stem.split("-rerun-", 1)[0]
        if "-rerun-" in p.stem and base in modules:
            modules[base].reruns.append(read_run(p))
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


def named(tests: dict) -> str:
    """`a`, `b` and N more, from a ledger's failing-tests record."""
    first, total = tests.get("first", []), tests.get("total", 0)
    text = ", ".join(f"`{t}`" for t in first)
    return text + (f" and {total - len(first)} more" if total > len(first) else "")


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
    by_file = {m.file: m for m in modules}
    for file in [*order, *(m.file for m in modules if m.file not in rank)]:
        m = by_file.get(file)
        if m is None:
            lines.append(f"| `{file}` | not in the ledger | | | | | | |")
            continue
        c, final = m.counts(), m.final()
        tested = f"{len(final)}" + (f" ({m.untested()} not reached)" if m.untested() else "")
        if m.first.sample:
            tested += f" of {m.first.sample['file_mutants']}, sampled (shards {', '.join(m.shards())})"
        lines.append(
            f"| `{m.file}` | {tested} | {c['CaughtMutant']} | {c['MissedMutant']} | {c['Timeout']} "
            f"| {c['Unviable']} | {ratio(c)} | {len(m.killed_later())} |"
        )
    unexplained = 0
    for m in modules:
        lines += ["", f"### `{m.file}`", ""]
        for label, run in [("Run", m.first)] + [("Rerun", r) for r in m.reruns]:
            done = "" if run.finished else f", stopped after {len(run.outcomes)} of its {run.planned} mutants"
            if run.sample:
                k, n = run.sample["shard"].split("/")
                done += f"; a sample: round-robin shard {k} of {n}, every {n}th mutant of the file from the {k}th"
            lines.append(f"{label} at commit {run.commit} (cargo-mutants {run.version}{done}):")
            lines += ["", "```sh", run.command, "```", ""]
        final = m.final()
        if m.untested():
            lines += [f"{m.untested()} mutants of the file were not tested (the run was stopped).", ""]
        if m.unsampled():
            lines += [
                f"{m.unsampled()} of the file's {m.first.sample['file_mutants']} mutants are in no shard run "
                "so far: the caught ratio is the sample's, an estimate of the file's, not a count of it.",
                "",
            ]
        killed = m.killed_later()
        missed = [n for n, o, _ in final.values() if o == "MissedMutant"]
        timeouts = [(n, r) for n, o, r in final.values() if o == "Timeout"]
        if not killed and not missed and not timeouts:
            lines.append("Every viable mutant tested was caught.")
        for name, tests in killed.values():
            where, what = split_name(name)
            killers = named(tests) or "the rerun's tests"
            lines.append(f"- {where} `{what}`: missed, now killed by {killers}")
        for name in missed:
            where, what = split_name(name)
            if name in explanations:
                lines.append(f"- {where} `{what}`: equivalent: {explanations[name]}")
            else:
                unexplained += 1
                lines.append(f"- {where} `{what}`: **UNEXPLAINED** (missed, no new test, no equivalence)")
        for name, run in timeouts:
            where, what = split_name(name)
            failed = named(run.failing_tests.get(name, {}))
            also = f"; before that, failed: {failed}" if failed else ""
            lines.append(f"- {where} `{what}`: timeout (a test hangs on it){also}")
    ledgered = {m.file for m in modules}
    missed = {n for m in modules for n, o, _ in m.final().values() if o == "MissedMutant"}
    stale = sorted(e for e in explanations if e.split(":", 1)[0] in ledgered and e not in missed)
    if stale:
        lines += ["", "Explanations in `tools/mutants/explained.toml` that match no missed mutant any more "
                  "(the code moved or a test catches it now; re-check them): " + ", ".join(f"`{s}`" for s in stale)]
    return "\n".join(lines) + "\n", unexplained


BEGIN, END = "<!-- mutants report: begin (tools/mutants/report.py) -->", "<!-- mutants report: end -->"


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--ledger", type=Path, default=Path(__file__).parent / "ledger")
    parser.add_argument("--explained", type=Path, default=Path("tools/mutants/explained.toml"))
    parser.add_argument("--doc", type=Path, default=Path("docs/mutation-testing.md"))
    parser.add_argument("files", nargs="*", help="the order of the modules in the table (MUTANTS_FILES)")
    args = parser.parse_args()
    modules = load_modules(args.ledger)
    if not modules:
        print(f"no cargo-mutants run in {args.ledger}", file=sys.stderr)
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
