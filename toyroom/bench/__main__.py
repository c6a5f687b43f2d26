"""``python -m toyroom.bench [--quick] [--memory] [--households] [--out DIR]`` (what ``toyroom
bench`` runs): every performance number in one run; prints tables, writes ``DIR/bench.json``,
``DIR/perf.md`` and ``DIR/scaling.png``; with ``--memory``, only the brain's peak memory
(:mod:`.memory`, ``DIR/memory.json``; exit 1 when a run failed or went over the budget); with
``--households``, only the CPU per household day of ``toyroom eval --days``, batched against a
process pair a run (:mod:`.households`, ``DIR/households/``; exit 1 when the metrics differ or
the ratio is above its target)."""

from __future__ import annotations

import argparse
import sys
import tempfile
from collections.abc import Sequence
from pathlib import Path

from brain.model.size import MEMORY_BUDGET_GB

from .households import main as households
from .memory import main as memory
from .suite import main as suite


def main(argv: Sequence[str] | None = None) -> int:
    """``toyroom bench``: measure toyroom's performance numbers in one run; the exit status."""
    parser = argparse.ArgumentParser(
        prog="toyroom bench", description="toyroom's performance numbers, measured in one run."
    )
    parser.add_argument("--quick", action="store_true", help="fewer repeats and houses (under 3 minutes)")
    parser.add_argument("--memory", action="store_true", help="only the brain's peak memory (memory.py)")
    parser.add_argument(
        "--households",
        action="store_true",
        help="only the CPU per household day of toyroom eval --days, batched against a process pair a "
        "run (households.py)",
    )
    parser.add_argument("--out", type=Path, default=Path(tempfile.gettempdir()) / "toyroom-bench")
    args = parser.parse_args(argv)
    if args.households:
        return households(["--out", str(args.out / "households")])
    if args.memory:
        runs = memory(args.out)
        return 0 if all(r.code == 0 and r.peak_gb <= MEMORY_BUDGET_GB for r in runs) else 1
    suite(args.quick, args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
