"""Check that two commits behave the same: run ``toyroom run`` on ``paper-1`` and
``paper-robot`` and a ``toyroom eval`` (10 episodes, seed 7) at each, each from a ``git
worktree`` of its commit, and compare what they wrote, timing aside (issue 68: "mind.csv,
events.csv and metrics.json are byte-identical on paper-1, paper-robot and a 10-episode eval").

Compared, per run: ``mind.csv``, ``events.csv`` and ``settings.toml``; for the evaluation:
``metrics.json`` and ``episodes.json``. A file is the same when its bytes are; else a CSV is
compared column by column and a JSON document field by field, leaving out timing (a JSON key
:data:`TIMING` matches: wall and CPU seconds) and reporting apart what only the newer commit
has (a new metric, a new column), which is no difference. Anything else that differs, is
missing, or a run that fails, is a difference: exit 1, each named.

Both commits run with this Python (its environment must hold both commits' dependencies, as
the project's ``.venv`` does); each worktree is put first on ``PYTHONPATH`` (its nodes
inherit it), and the script checks that its packages are imported from there. The runs go
one after the other (timing is not compared, but a loaded machine slows them all).

Usage: python .ci/same_outputs.py OLD NEW [--episodes 10] [--seed 7] [--max-ticks N]
       [--work DIR] [--keep]
"""

from __future__ import annotations

import argparse
import csv
import io
import json
import os
import re
import shutil
import subprocess
import sys
import tempfile
from dataclasses import dataclass, field
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SCENARIOS = ("paper-1", "paper-robot")
RUN_FILES = ("mind.csv", "events.csv", "settings.toml")
EVAL_FILES = ("metrics.json", "episodes.json")
TIMING = re.compile(r"^timing$|(^|_)seconds(_|$)|^cpu_")
"""The JSON keys left out of the comparison: the evaluation's ``timing`` block and every
``seconds`` field (an episode's ``seconds``, its ``run_seconds``)."""
PACKAGES = ("protocol", "bridge", "sim2d", "brain", "toyroom")


@dataclass
class Findings:
    """What the comparison found: differences (each fails it) and what only the newer commit
    writes (reported, not failing)."""

    differences: list[str] = field(default_factory=list)
    added: list[str] = field(default_factory=list)
    same: list[str] = field(default_factory=list)


def git(*args: str) -> str:
    """``git ARGS`` in this checkout; its standard output, stripped."""
    return subprocess.run(
        ["git", "-C", str(ROOT), *args], check=True, capture_output=True, text=True
    ).stdout.strip()


def check_imports(source: Path, env: dict[str, str]) -> None:
    """Fail unless the packages a run imports under ``env`` are those of ``source``."""
    probe = f"import {', '.join(PACKAGES)}; print('\\n'.join(m.__file__ for m in ({', '.join(PACKAGES)})))"
    files = subprocess.run(
        [sys.executable, "-c", probe], cwd=source, env=env, check=True, capture_output=True, text=True
    )
    stray = [f for f in files.stdout.split() if not Path(f).resolve().is_relative_to(source.resolve())]
    if stray:
        raise SystemExit(f"{source}: the packages are imported from elsewhere: {stray}")


def run_commit(commit: str, source: Path, out: Path, args: argparse.Namespace) -> list[str]:
    """Run the scenarios and the evaluation at ``commit`` (checked out at ``source``) into
    ``out``; the failures, each in one line with its log's tail."""
    git("worktree", "add", "--force", "--detach", str(source), commit)
    env = {**os.environ, "PYTHONPATH": str(source)}
    check_imports(source, env)
    out.mkdir(parents=True)
    toyroom = [sys.executable, "-m", "toyroom"]
    commands = {
        scenario: [*toyroom, "run", "--scenario", scenario, "--out", scenario, "--no-live"]
        for scenario in SCENARIOS
    }
    commands["eval"] = [
        *toyroom,
        "eval",
        "--episodes",
        str(args.episodes),
        "--seed",
        str(args.seed),
        "--out",
        "eval",
    ]
    if args.max_ticks is not None:
        commands["eval"] += ["--max-ticks", str(args.max_ticks)]
    failures = []
    for name, command in commands.items():  # relative --out: the same command line at both
        print(f"{commit[:10]}: {' '.join(command[2:])}", flush=True)
        done = subprocess.run(command, cwd=out, env=env, capture_output=True, text=True)
        (out / f"{name}.log").write_text(done.stdout + done.stderr, encoding="utf-8")
        if done.returncode != 0:
            failures.append(
                f"{commit[:10]} {name}: exit {done.returncode}: {(done.stdout + done.stderr)[-400:]}"
            )
    return failures


def without_timing(value: object) -> object:
    """``value`` (parsed JSON) with every key :data:`TIMING` matches left out, at any depth."""
    if isinstance(value, dict):
        return {k: without_timing(v) for k, v in value.items() if not TIMING.search(k)}
    if isinstance(value, list):
        return [without_timing(v) for v in value]
    return value


def compare_json(old: object, new: object, where: str, found: Findings) -> None:
    """Add to ``found`` every field of ``old`` that ``new`` lacks or holds otherwise, and every
    field only ``new`` has (reported apart), by path."""
    if isinstance(old, dict) and isinstance(new, dict):
        for key in old.keys() | new.keys():
            path = f"{where}.{key}"
            if key not in new:
                found.differences.append(f"{path}: missing at the newer commit")
            elif key not in old:
                found.added.append(f"{path} (only at the newer commit)")
            else:
                compare_json(old[key], new[key], path, found)
    elif isinstance(old, list) and isinstance(new, list) and len(old) == len(new):
        for i, (a, b) in enumerate(zip(old, new, strict=True)):
            compare_json(a, b, f"{where}[{i}]", found)
    elif old != new or type(old) is not type(new):
        found.differences.append(f"{where}: {json.dumps(old)[:80]} -> {json.dumps(new)[:80]}")


def compare_csv(old: str, new: str, name: str, found: Findings) -> None:
    """Add to ``found`` the columns only ``new`` has (reported apart) and every difference of
    the columns both have (missing columns, other rows), the first few rows by number."""
    old_rows, new_rows = list(csv.DictReader(io.StringIO(old))), list(csv.DictReader(io.StringIO(new)))
    old_columns = next(csv.reader(io.StringIO(old)), [])
    new_columns = next(csv.reader(io.StringIO(new)), [])
    found.added += [
        f"{name}: column {c} (only at the newer commit)" for c in new_columns if c not in old_columns
    ]
    missing = [c for c in old_columns if c not in new_columns]
    if missing:
        found.differences.append(f"{name}: columns {missing} missing at the newer commit")
    if len(old_rows) != len(new_rows):
        found.differences.append(f"{name}: {len(old_rows)} rows -> {len(new_rows)}")
    shared = [c for c in old_columns if c in new_columns]
    rows = [
        i
        for i, (a, b) in enumerate(zip(old_rows, new_rows, strict=False))
        if [a[c] for c in shared] != [b[c] for c in shared]
    ]
    for i in rows[:5]:
        found.differences.append(f"{name} row {i + 2}: {old_rows[i]} -> {new_rows[i]}")
    if len(rows) > 5:
        found.differences.append(f"{name}: {len(rows) - 5} more rows differ")


def compare_file(old: Path, new: Path, name: str, found: Findings) -> None:
    """Compare one output: the same bytes, else by field (JSON) or column (CSV), timing aside."""
    if not old.is_file() or not new.is_file():
        found.differences.append(f"{name}: missing at the {'older' if not old.is_file() else 'newer'} commit")
        return
    if old.read_bytes() == new.read_bytes():
        found.same.append(f"{name}: byte-identical")
        return
    before = len(found.differences)
    if name.endswith(".json"):
        compare_json(
            without_timing(json.loads(old.read_text())),
            without_timing(json.loads(new.read_text())),
            "",
            found,
        )
    elif name.endswith(".csv"):
        compare_csv(old.read_text(), new.read_text(), name, found)
    else:
        found.differences.append(f"{name}: the bytes differ")
    if len(found.differences) == before:
        found.same.append(f"{name}: identical, timing aside")


def compare(old: Path, new: Path) -> Findings:
    """Compare every output of :data:`SCENARIOS` and the evaluation under ``old`` and ``new``."""
    found = Findings()
    names = [f"{s}/{f}" for s in SCENARIOS for f in RUN_FILES] + [f"eval/{f}" for f in EVAL_FILES]
    for name in names:
        compare_file(old / name, new / name, name, found)
    return found


def parser() -> argparse.ArgumentParser:
    """This script's options."""
    options = argparse.ArgumentParser(description=__doc__.split("\n\n")[0], prog="same_outputs.py")
    options.add_argument("old", help="the older commit (any git revision)")
    options.add_argument("new", help="the newer commit (any git revision)")
    options.add_argument("--episodes", type=int, default=10, help="the evaluation's episodes (default: 10)")
    options.add_argument("--seed", type=int, default=7, help="the evaluation's seed (default: 7)")
    options.add_argument(
        "--max-ticks", type=int, help="the evaluation's ticks per episode (default: its own)"
    )
    options.add_argument(
        "--work", type=Path, help="where the worktrees and outputs go (default: a temporary folder)"
    )
    options.add_argument("--keep", action="store_true", help="keep the worktrees and outputs")
    return options


def main(argv: list[str] | None = None) -> int:
    """Run both commits, compare, print the findings; 0 when nothing differs, else 1."""
    args = parser().parse_args(argv)
    work = args.work or Path(tempfile.mkdtemp(prefix="same-outputs-"))
    commits = {
        label: git("rev-parse", "--verify", f"{rev}^{{commit}}")
        for label, rev in (("old", args.old), ("new", args.new))
    }
    failures: list[str] = []
    try:
        for label, commit in commits.items():
            failures += run_commit(commit, work / f"{label}-src", work / label, args)
        found = compare(work / "old", work / "new")
    finally:
        for label in commits:
            if (work / f"{label}-src").exists():
                git("worktree", "remove", "--force", str(work / f"{label}-src"))
        if not args.keep and args.work is None:
            shutil.rmtree(work, ignore_errors=True)
    print(f"\n{commits['old'][:10]} -> {commits['new'][:10]}")
    for line in found.same:
        print(f"  same: {line}")
    for line in found.added:
        print(f"  new:  {line}")
    for line in failures + found.differences:
        print(f"  DIFFERENT: {line}")
    print("identical" if not (failures or found.differences) else "DIFFERENT")
    return 1 if failures or found.differences else 0


if __name__ == "__main__":
    sys.exit(main())
