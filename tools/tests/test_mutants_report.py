"""tools/mutants/record.py and report.py on hand-made cargo-mutants output: runs and reruns."""
import json
import subprocess
import sys
from pathlib import Path

TOOLS = Path(__file__).resolve().parents[1] / "mutants"
FILE = "src/k.rs"
MISSED_THEN_KILLED = f"{FILE}:3:5: replace + with - in f"
EQUIVALENT = f"{FILE}:4:9: replace < with <= in f"
UNEXPLAINED = f"{FILE}:5:9: replace * with / in f"
CAUGHT = f"{FILE}:6:1: replace f -> f64 with 0.0"
HANG = f"{FILE}:7:2: delete ! in g"
UNVIABLE = f"{FILE}:8:2: replace g -> usize with 1"

CAUGHT_LOG = """running 3 tests
test k::tests::new_test ... FAILED
failures:

---- k::tests::new_test stdout ----
assertion failed

failures:
    k::tests::new_test
    k::tests::other_test

test result: FAILED. 1 passed; 2 failed
"""
HANG_LOG = "test k::tests::fast ... ok\ntest k::tests::slow_check ... FAILED\n*** result: Timeout\n"


def moved(name: str, lines: int) -> str:
    """The same mutant after `lines` lines were inserted above its function."""
    place, what = name.split(": ", 1)
    file, line, col = place.split(":")
    return f"{file}:{int(line) + lines}:{col}: {what}"


def write_run(directory: Path, outcomes: dict[str, str], planned: int, finished: bool, logs=None,
              function_line: int = 1, command: str = "cargo mutants --file src/k.rs") -> None:
    out = directory / "mutants.out"
    (out / "log").mkdir(parents=True)
    entries = [{"scenario": "Baseline", "summary": "Success", "log_path": "log/baseline.log"}]
    for i, (name, summary) in enumerate(outcomes.items()):
        log = f"log/m{i}.log"
        (out / log).write_text((logs or {}).get(name, ""))
        _, line, col = name.split(": ", 1)[0].split(":")
        mutant = {
            "name": name,
            "span": {"start": {"line": int(line), "column": int(col)}},
            "function": {"span": {"start": {"line": function_line}}},
        }
        entries.append({"scenario": {"Mutant": mutant}, "summary": summary, "log_path": log})
    (out / "outcomes.json").write_text(json.dumps({
        "outcomes": entries, "cargo_mutants_version": "27.1.0",
        "end_time": "2026-01-01T00:00:00Z" if finished else None,
    }))
    (out / "mutants.json").write_text(json.dumps([{} for _ in range(planned)]))
    (directory / "command.txt").write_text(command)
    (directory / "commit.txt").write_text("abc1234")


def record(tmp_path: Path, *runs: str) -> None:
    for run in runs:
        subprocess.run(
            [sys.executable, str(TOOLS / "record.py"), str(tmp_path / "out" / run), "--ledger",
             str(tmp_path / "ledger")],
            check=True, capture_output=True,
        )


def run_report(tmp_path: Path, explained: str) -> tuple[int, str]:
    doc = tmp_path / "page.md"
    doc.write_text("intro\n<!-- mutants report: begin (tools/mutants/report.py) -->\nold\n"
                   "<!-- mutants report: end -->\ntail\n")
    (tmp_path / "explained.toml").write_text(explained)
    done = subprocess.run(
        [sys.executable, str(TOOLS / "report.py"), "--ledger", str(tmp_path / "ledger"), "--explained",
         str(tmp_path / "explained.toml"), "--doc", str(doc), FILE, "src/other.rs"],
        capture_output=True, text=True,
    )
    return done.returncode, doc.read_text()


def make_runs(tmp_path: Path) -> None:
    write_run(tmp_path / "out" / "k", {
        MISSED_THEN_KILLED: "MissedMutant", EQUIVALENT: "MissedMutant", UNEXPLAINED: "MissedMutant",
        CAUGHT: "CaughtMutant", UNVIABLE: "Unviable",
    }, planned=7, finished=False)
    write_run(tmp_path / "out" / "k-rerun-20260101T000000", {
        MISSED_THEN_KILLED: "CaughtMutant", EQUIVALENT: "MissedMutant", UNEXPLAINED: "MissedMutant",
        HANG: "Timeout",
    }, planned=5, finished=False, logs={MISSED_THEN_KILLED: CAUGHT_LOG, HANG: HANG_LOG})
    record(tmp_path, "k", "k-rerun-20260101T000000")


def test_counts_ratio_and_the_account_of_every_missed_mutant(tmp_path: Path):
    make_runs(tmp_path)
    code, page = run_report(tmp_path, f'[[mutant]]\nname = "{EQUIVALENT}"\nequivalent = "same values"\n')
    assert code == 1  # one missed mutant has neither a killing test nor an equivalence
    assert page.startswith("intro\n") and page.endswith("<!-- mutants report: end -->\ntail\n")
    assert "old" not in page
    # 6 of 7 tested; caught 2 (one after the rerun), missed 2, timeout 1, unviable 1;
    # ratio (2 + 1) / (2 + 2 + 1) = 60 %; one mutant was missed before the new tests
    assert "| `src/k.rs` | 6 (1 not reached) | 2 | 2 | 1 | 1 | 60.0 % | 1 |" in page
    assert "| `src/other.rs` | not in the ledger |" in page
    assert "3:5 `replace + with - in f`: missed, now killed by `k::tests::new_test`, `k::tests::other_test`" in page
    assert "4:9 `replace < with <= in f`: equivalent: same values" in page
    assert "5:9 `replace * with / in f`: **UNEXPLAINED**" in page
    assert "7:2 `delete ! in g`: timeout (a test hangs on it); before that, failed: `k::tests::slow_check`" in page
    assert "stopped after 5 of its 7 mutants" in page and "Rerun at commit abc1234" in page


def test_every_missed_mutant_explained_passes(tmp_path: Path):
    make_runs(tmp_path)
    explained = "".join(f'[[mutant]]\nname = "{n}"\nequivalent = "why"\n' for n in (EQUIVALENT, UNEXPLAINED))
    code, page = run_report(tmp_path, explained)
    assert code == 0
    assert "UNEXPLAINED" not in page and "match no missed mutant" not in page


def test_the_report_needs_only_the_ledger(tmp_path: Path):
    make_runs(tmp_path)
    for path in (tmp_path / "out").rglob("*"):
        if path.is_file():
            path.unlink()
    code, page = run_report(tmp_path, "")
    assert "| `src/k.rs` | 6 (1 not reached) | 2 | 2 | 1 | 1 | 60.0 % | 1 |" in page
    assert "missed, now killed by `k::tests::new_test`" in page


def test_a_rerun_after_code_moved_the_mutants_matches_them_by_place_in_their_function(tmp_path: Path):
    write_run(tmp_path / "out" / "k", {
        MISSED_THEN_KILLED: "MissedMutant", UNEXPLAINED: "MissedMutant", CAUGHT: "CaughtMutant",
    }, planned=3, finished=True)
    # ten lines were added above f; the iterate rerun retests what was not caught: the killed
    # mutant at its new line, and nothing of UNEXPLAINED's line, whose code was deleted
    write_run(tmp_path / "out" / "k-rerun-20260101T000000", {moved(MISSED_THEN_KILLED, 10): "CaughtMutant"},
              planned=1, finished=True, logs={moved(MISSED_THEN_KILLED, 10): CAUGHT_LOG}, function_line=11,
              command="cargo mutants --file src/k.rs --iterate")
    record(tmp_path, "k", "k-rerun-20260101T000000")
    code, page = run_report(tmp_path, "")
    assert code == 0
    assert "| `src/k.rs` | 2 | 2 | 0 | 0 | 0 | 100.0 % | 1 |" in page
    assert "13:5 `replace + with - in f`: missed, now killed by `k::tests::new_test`" in page
    assert "UNEXPLAINED" not in page


def test_a_sampled_run_is_reported_as_a_sample_of_the_file(tmp_path: Path):
    """A MUTANTS_SHARD run: the ledger keeps the shard and the file's count, the report says
    how much of the file was sampled and that its ratio is the sample's."""
    directory = tmp_path / "out" / "k"
    write_run(directory, {CAUGHT: "CaughtMutant", MISSED_THEN_KILLED: "CaughtMutant"}, planned=2, finished=True,
              command="cargo mutants --file src/k.rs --shard 0/4 --sharding round-robin")
    (directory / "file-mutants.txt").write_text("8\n")
    record(tmp_path, "k")
    entry = json.loads((tmp_path / "ledger" / "k.json").read_text())
    assert entry["sample"] == {"shard": "0/4", "file_mutants": 8}
    code, page = run_report(tmp_path, "")
    assert code == 0
    assert "| `src/k.rs` | 2 of 8, sampled (shards 0/4) | 2 | 0 |" in page
    assert "6 of the file's 8 mutants are in no shard run so far" in page


def test_a_new_first_run_supersedes_the_reruns_of_the_one_it_replaces(tmp_path: Path):
    make_runs(tmp_path)
    # the file is mutated again from scratch (same run directory name): UNEXPLAINED, which the
    # old rerun had still missed, is caught now and must not be overridden by that rerun
    for path in sorted((tmp_path / "out" / "k").rglob("*"), reverse=True):
        path.unlink() if path.is_file() else path.rmdir()
    write_run(tmp_path / "out" / "k", {UNEXPLAINED: "CaughtMutant", CAUGHT: "CaughtMutant"},
              planned=2, finished=True)
    record(tmp_path, "k")
    assert [p.name for p in (tmp_path / "ledger").glob("*.json")] == ["k.json"]
    code, page = run_report(tmp_path, "")
    assert code == 0
    assert "| `src/k.rs` | 2 | 2 | 0 | 0 | 0 | 100.0 % | 0 |" in page
