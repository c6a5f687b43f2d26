"""``python -m toyroom.bench.households`` (``toyroom bench --households``): the CPU a households
evaluation (``toyroom eval --days N``) takes per household day with a process pair a run
(``--batch 1``) and batched, a household's chain days on one engine and one brain (its
default, or ``--batch K``; :mod:`toyroom.evaluation.dayserver`), measured in one run on the
same households.

Each mode is one ``toyroom eval`` process, run one after the other; its CPU is the user and
system seconds of it and every process it started and waited for (the evaluator, the engines,
the brains, the scenario generator: ``RUSAGE_CHILDREN`` before and after), not wall time,
so other work on the machine counts less. It prints both, their ratio against the target
(:data:`TARGET`, issue 67) and whether the two ``metrics.json`` are the same but timing;
exit 1 when they are not, when a run failed, or when the ratio is above the target.
"""

from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
import tempfile
import time
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

TARGET = 0.8
"""Batched households' CPU per household day, at most this share of a process pair a run's."""
HOUSEHOLDS = (
    *("--kind", "tasks", "--perception", "embodied", "--minds", "rich", "--policies", "tom"),
    *("--workers", "2"),
)
"""The households measured (issue 51's command with one acting policy), with ``--episodes``,
``--days``, ``--seed`` and ``--max-ticks`` from the options."""
OPERATIONAL = ("timing", "command", "failed_runs_retried")
"""What may differ between the two runs' ``metrics.json``."""


@dataclass
class Measured:
    """One mode's run: its CPU seconds (the whole process tree), wall seconds, exit status."""

    batch: int | None
    cpu_s: float
    wall_s: float
    code: int
    out: Path


def children_cpu() -> float:
    """User and system seconds of this process's finished children (and theirs, reaped)."""
    used = resource.getrusage(resource.RUSAGE_CHILDREN)
    return used.ru_utime + used.ru_stime


def mode(batch: int | None) -> str:
    """How a mode is named: ``--batch K``, or ``batched`` (``toyroom eval``'s default)."""
    return "batched" if batch is None else f"--batch {batch}"


def run_mode(argv: Sequence[str], batch: int | None, out: Path) -> Measured:
    """``toyroom eval ARGV [--batch BATCH] --fresh --out OUT``, its CPU and wall seconds."""
    batched = [] if batch is None else ["--batch", str(batch)]
    command = [sys.executable, "-m", "toyroom", "eval", *argv, *batched, "--fresh", "--out", str(out)]
    cpu, wall = children_cpu(), time.monotonic()
    done = subprocess.run(command, capture_output=True, text=True, check=False)
    measured = Measured(batch, children_cpu() - cpu, time.monotonic() - wall, done.returncode, out)
    if done.returncode != 0:
        said = done.stderr[-2000:]
        print(f"toyroom eval {mode(batch)} exited {done.returncode}:\n{said}", file=sys.stderr)
    return measured


def scores(out: Path) -> dict[str, Any]:
    """``metrics.json`` of ``out`` but :data:`OPERATIONAL`, as ``{path: value}``."""

    def flat(value: Any, path: str) -> dict[str, Any]:
        if isinstance(value, dict):
            items = [(k, v) for k, v in value.items() if k not in OPERATIONAL]
            return {p: x for k, v in items for p, x in flat(v, f"{path}/{k}").items()}
        if isinstance(value, list):
            return {p: x for i, v in enumerate(value) for p, x in flat(v, f"{path}[{i}]").items()}
        return {path: value}

    return flat(json.loads((out / "metrics.json").read_text()), "")


def measure(
    households: int, days: int, seed: int, max_ticks: int, batch: int | None, out: Path
) -> dict[str, Any]:
    """Both modes on the same households (a process pair a run first), and what they give."""
    argv = [*HOUSEHOLDS, "--episodes", str(households), "--days", str(days), "--seed", str(seed)]
    argv += ["--max-ticks", str(max_ticks)]
    alone = run_mode(argv, 1, out / "alone")
    batched = run_mode(argv, batch, out / "batched")
    household_days = households * days
    same = alone.code == batched.code == 0 and scores(alone.out) == scores(batched.out)
    per_day = {mode(m.batch): m.cpu_s / household_days for m in (alone, batched)}
    one, many = per_day[mode(1)], per_day[mode(batch)]
    return {
        "command": " ".join(["toyroom", "eval", *argv]),
        "household_days": household_days,
        "cpu_s_per_household_day": per_day,
        "wall_s": {mode(m.batch): m.wall_s for m in (alone, batched)},
        "ratio": many / one if one > 0 else None,
        "target": TARGET,
        "same_metrics": same,
        "failed": [mode(m.batch) for m in (alone, batched) if m.code != 0],
    }


def show(numbers: dict[str, Any]) -> None:
    """The numbers as a few lines."""
    print(f"households: {numbers['command']} ({numbers['household_days']} household days)")
    for name, cpu in numbers["cpu_s_per_household_day"].items():
        print(f"  {name}: {cpu:.2f} CPU s per household day ({numbers['wall_s'][name]:.0f} s wall)")
    ratio = numbers["ratio"]
    shown = "-" if ratio is None else f"{ratio:.2f}"
    print(f"  ratio batched / a process pair a run: {shown} (target <= {TARGET})")
    print(f"  metrics.json the same but timing: {'yes' if numbers['same_metrics'] else 'NO'}")


def parser() -> argparse.ArgumentParser:
    """The options: the households measured, and where to keep them."""
    options = argparse.ArgumentParser(
        prog="python -m toyroom.bench.households",
        description="CPU per household day of toyroom eval --days: a process pair a run against batched.",
    )
    options.add_argument("--households", type=int, default=2, help="households (default: %(default)s)")
    options.add_argument("--days", type=int, default=3, help="days of each (default: %(default)s)")
    options.add_argument("--seed", type=int, default=11, help="the sweep's seed (default: %(default)s)")
    options.add_argument("--max-ticks", type=int, default=250, help="ticks a day (default: %(default)s)")
    options.add_argument(
        "--batch", type=int, help="batched: at most this many runs a process pair (default: a household's)"
    )
    options.add_argument("--out", type=Path, help="keep both evaluations here (default: a temporary folder)")
    return options


def main(argv: Sequence[str] | None = None) -> int:
    """``python -m toyroom.bench.households``; exit 0 when both runs finished, their metrics
    agree and the ratio meets the target."""
    options = parser()
    args = options.parse_args(argv)
    least = [
        ("--households", args.households, 1),
        ("--days", args.days, 1),
        ("--max-ticks", args.max_ticks, 1),
    ]
    least += [("--batch", 2 if args.batch is None else args.batch, 2)]
    for flag, value, bound in least:
        if value < bound:
            print(f"{options.prog}: {flag} must be at least {bound}, got {value}", file=sys.stderr)
            return 2
    with tempfile.TemporaryDirectory() as scratch:
        out = args.out or Path(scratch)
        numbers = measure(args.households, args.days, args.seed, args.max_ticks, args.batch, out)
        if args.out is not None:
            (out / "households.json").write_text(json.dumps(numbers, indent=2) + "\n")
    show(numbers)
    ratio = numbers["ratio"]
    met = numbers["same_metrics"] and not numbers["failed"] and ratio is not None and ratio <= TARGET
    return 0 if met else 1


if __name__ == "__main__":
    sys.exit(main())
