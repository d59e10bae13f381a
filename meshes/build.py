#!/usr/bin/env python3
"""Regenerate the mesh includes of every scene, or check that the committed ones are
current.

    .venv/bin/python meshes/build.py           # "test" includes → meshes/<scene>/   (make meshes)
    .venv/bin/python meshes/build.py --full    # "full" includes → meshes/full/<scene>/ (make meshes-full)
    .venv/bin/python meshes/build.py --check   # regenerate "test" into a temp dir, compare bytes

Each scene is a module ``meshes/<scene>.py`` with ``generate(out: Path, size: str) ->
list[Path]`` (see meshes/README.md). A scene whose module does not exist yet is skipped with a
note. ``--check`` lists stale (different bytes), missing (generated but not committed) and extra
(committed ``*.bdf`` the generator no longer writes) files and exits with 1 on any of them.
"""
from __future__ import annotations

import argparse
import filecmp
import importlib
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
SCENES = ["plates", "fourbar", "robot", "blade"]


def scene_modules() -> list[tuple[str, object]]:
    """The scene modules that exist, in SCENES order; a missing one is reported and skipped.
    They are found next to this script (Python puts a script's directory first on its path)."""
    found = []
    for name in SCENES:
        if not (HERE / f"{name}.py").is_file():
            print(f"note: meshes/{name}.py does not exist (yet); scene '{name}' skipped")
            continue
        found.append((name, importlib.import_module(name)))
    return found


def build(size: str) -> None:
    root = HERE if size == "test" else HERE / "full"
    for name, module in scene_modules():
        paths = module.generate(root / name, size)
        print(f"{name}: wrote {len(paths)} file(s) to {(root / name).relative_to(HERE.parent)}")


def check() -> int:
    """Regenerate the "test" includes in a temp dir and compare them with the committed ones."""
    problems = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, module in scene_modules():
            fresh_dir = Path(tmp) / name
            fresh = {p.name for p in module.generate(fresh_dir, "test")}
            committed_dir = HERE / name
            committed = {p.name for p in committed_dir.glob("*.bdf")} if committed_dir.is_dir() else set()
            for f in sorted(fresh - committed):
                problems.append(f"missing: meshes/{name}/{f} (generated, not committed)")
            for f in sorted(committed - fresh):
                problems.append(f"extra:   meshes/{name}/{f} (committed, no longer generated)")
            for f in sorted(fresh & committed):
                if not filecmp.cmp(fresh_dir / f, committed_dir / f, shallow=False):
                    problems.append(f"stale:   meshes/{name}/{f} (differs from the generator's output)")
            print(f"{name}: {len(fresh)} generated, {len(committed)} committed")
    for p in problems:
        print(p)
    if problems:
        print(f"{len(problems)} problem(s): run `make meshes` and commit meshes/<scene>/")
        return 1
    print("committed includes are current")
    return 0


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    mode = ap.add_mutually_exclusive_group()
    mode.add_argument("--full", action="store_true", help="write the full-size variants to meshes/full/")
    mode.add_argument("--check", action="store_true", help="compare committed test includes with fresh ones")
    args = ap.parse_args()
    if args.check:
        return check()
    build("full" if args.full else "test")
    return 0


if __name__ == "__main__":
    sys.exit(main())
