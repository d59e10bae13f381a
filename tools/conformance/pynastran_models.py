#!/usr/bin/env python3
"""Run paraflex over the structural decks of pyNastran's public model collection.

The collection is the ``models/`` folder of the pyNastran repository (not vendored here):

    git clone --depth 1 https://github.com/SteveDoyle2/pyNastran /tmp/pyNastran
    .venv/bin/python tools/conformance/pynastran_models.py --models /tmp/pyNastran/models \\
        [--paraflex target/release/paraflex] [--run] [-o docs/conformance-models.md]

A structural deck is a file (``.bdf``, ``.dat``, ``.nas``, any case) whose executive control
asks for SOL 101, 103, 108, 109, 110, 111 or 112 (or their names: SESTATIC, SEMODES, SEDCEIG,
SEDFREQ, SEDTRAN, SEMCEIG, SEMFREQ, SEMTRAN); include files and decks of other sequences are
left out. Each is read by ``paraflex check --json``; with ``--run`` the decks that pass are also
run (``paraflex run``, into a scratch directory, with a time limit). The report lists every deck
with its outcome, then the cards that stop decks, ranked by the number of decks each stops and by
the number it alone stops (the decks that would read if that one card were supported): the order
in which to add cards.
"""
from __future__ import annotations

import argparse
import collections
import json
import re
import subprocess
import tempfile
from pathlib import Path

from paraflex_tools import runner

SEQUENCES = r"101|103|108|109|110|111|112|SESTATIC|SEMODES|SEDCEIG|SEDFREQ|SEDTRAN|SEMCEIG|SEMFREQ|SEMTRAN"
SOL_LINE = re.compile(rf"^\s*SOL\s+({SEQUENCES})\b", re.I | re.M)
EXTENSIONS = {".bdf", ".dat", ".nas"}
UNSUPPORTED = re.compile(r"unsupported (bulk data card|case control command|executive control statement) '([^']+)'")


def structural_decks(models: Path) -> list[tuple[Path, str]]:
    """(deck, its SOL) of every structural deck under ``models``, sorted by path."""
    decks = []
    for path in sorted(models.rglob("*")):
        if not path.is_file() or path.suffix.lower() not in EXTENSIONS:
            continue
        head = path.read_text(errors="replace").split("CEND", 1)[0] if path.stat().st_size else ""
        match = SOL_LINE.search(head)
        if match:
            decks.append((path, match.group(1).upper()))
    return decks


def check(binary: Path, deck: Path, timeout: float) -> tuple[str, list[str], str]:
    """(outcome, unsupported names, first other error) of ``paraflex check --json``."""
    try:
        p = subprocess.run([str(binary), "check", "--json", str(deck)], capture_output=True, text=True,
                           timeout=timeout, cwd=deck.parent)
    except subprocess.TimeoutExpired:
        return "timeout", [], f"check took longer than {timeout} s"
    if p.returncode == 0:
        return "reads", [], ""
    try:
        errors = json.loads(p.stdout)["errors"]
    except (json.JSONDecodeError, KeyError):
        return f"exit {p.returncode}", [], (p.stderr or p.stdout).strip().splitlines()[-1:][0] if (p.stderr or p.stdout).strip() else ""
    names = sorted({m.group(2).upper() for e in errors for m in [UNSUPPORTED.search(e["message"])] if m})
    others = [e["message"] for e in errors if not UNSUPPORTED.search(e["message"])]
    outcome = "unsupported" if names else "invalid"
    return outcome, names, others[0][:160] if others else ""


def run(binary: Path, deck: Path, timeout: float) -> tuple[str, str]:
    with tempfile.TemporaryDirectory() as scratch:
        try:
            p = subprocess.run([str(binary), "run", str(deck), "-o", str(Path(scratch) / "out.h5")],
                               capture_output=True, text=True, timeout=timeout, cwd=deck.parent)
        except subprocess.TimeoutExpired:
            return "run timeout", f"longer than {timeout} s"
    if p.returncode == 0:
        return "runs", ""
    last = [line for line in p.stderr.splitlines() if line.startswith("error")]
    return f"run exit {p.returncode}", (last[0] if last else p.stderr.strip()[-160:])[:160]


def greedy_order(blocked: list[set[str]], steps: int) -> list[tuple[str, int]]:
    """Cards in the order that unblocks the most decks at each step: (name, decks read by then
    among ``blocked``, the unsupported-name sets of the decks that do not read)."""
    supported: set[str] = set()
    order = []
    for _ in range(steps):
        remaining = [b - supported for b in blocked if b - supported]
        if not remaining:
            break

        def gain(name: str) -> tuple[int, int]:
            return sum(r <= {name} for r in remaining), sum(name in r for r in remaining)

        best = max(sorted({n for r in remaining for n in r}), key=gain)
        supported.add(best)
        order.append((best, sum(not (b - supported) for b in blocked)))
    return order


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--models", type=Path, required=True, help="the models/ folder of a pyNastran checkout")
    ap.add_argument("--paraflex", default=None)
    ap.add_argument("--run", action="store_true", help="also run the decks that read")
    ap.add_argument("--timeout", type=float, default=120.0)
    ap.add_argument("-o", "--output", type=Path, help="markdown report (default: print)")
    ap.add_argument("--label", default="", help="where the collection came from (e.g. its commit), for the report")
    ap.add_argument("--greedy", type=int, default=40, help="length of the card order of the report")
    args = ap.parse_args()
    binary = runner.find_binary(args.paraflex).resolve()
    decks = structural_decks(args.models)
    if not decks:
        raise SystemExit(f"no structural deck under {args.models}")
    rows, blockers, alone = [], collections.Counter(), collections.Counter()
    for deck, sol in decks:
        outcome, names, detail = check(binary, deck, args.timeout)
        if outcome == "reads" and args.run:
            outcome, detail = run(binary, deck, args.timeout)
        blockers.update(names)
        if len(names) == 1:
            alone.update(names)
        rows.append((deck.relative_to(args.models).as_posix(), sol, outcome, " ".join(names), detail))
        print(f"{rows[-1][0]}: SOL {sol}: {outcome} {' '.join(names)} {detail}", flush=True)
    counts = collections.Counter(r[2] for r in rows)
    read = counts["reads"] + sum(v for k, v in counts.items() if k.startswith("run"))
    lines = [
        "# paraflex over pyNastran's model collection",
        "",
        f"Made by `tools/conformance/pynastran_models.py{' --run' if args.run else ''}` (its header says how to get "
        "the collection)" + (f"; collection: {args.label}" if args.label else "") + ". Structural decks (SOL 101, 103, 108–112): "
        f"**{len(rows)}**; read by `paraflex check`: **{read}** ({100 * read / len(rows):.0f} %)"
        + (f"; run to the end: **{counts['runs']}**" if args.run else "") + ".",
        "",
        "| outcome | decks |",
        "|---|---|",
        *[f"| {k} | {v} |" for k, v in counts.most_common()],
        "",
        "## Cards and commands that stop decks",
        "",
        "decks: how many decks name it; alone: how many it is the only unsupported name of.",
        "",
        "| name | decks | alone |",
        "|---|---|---|",
        *[f"| {name} | {n} | {alone[name]} |" for name, n in blockers.most_common()],
        "",
        "## An order to add them",
        "",
        "Each step adds the name that makes the most decks free of unsupported names (ties: the one",
        "named by most decks); the column is the number of decks with no unsupported name after it",
        f"(now {read + counts['invalid']}, of which {counts['invalid']} stop on other errors; 60 % of the collection is"
        f" {-(-len(rows) * 60 // 100)}).",
        "",
        "| step | name | decks without unsupported names |",
        "|---|---|---|",
        *[f"| {k + 1} | {name} | {n + read + counts['invalid']} |"
          for k, (name, n) in enumerate(greedy_order([set(r[3].split()) for r in rows if r[3]], args.greedy))],
        "",
        "## Every deck",
        "",
        "| deck | SOL | outcome | unsupported | first other error |",
        "|---|---|---|---|---|",
        *[f"| `{d}` | {s} | {o} | {n} | {e.replace('|', '/')} |" for d, s, o, n, e in rows],
        "",
    ]
    text = "\n".join(lines)
    if args.output:
        args.output.write_text(text)
        print(f"wrote {args.output}")
    else:
        print(text)


if __name__ == "__main__":
    main()
