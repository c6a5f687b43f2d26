"""``toyroom bench``: measure the transport, lock-step and brain speeds in one run (it hands
over to ``python -m toyroom.bench``)."""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

from ..subcommand import Subcommand


def options(bench: argparse.ArgumentParser) -> None:
    """``toyroom bench``'s options."""
    bench.add_argument("--quick", action="store_true", help="fewer repeats and houses (under 3 minutes)")
    bench.add_argument(
        "--memory",
        action="store_true",
        help="only the brain's peak resident memory with miss = 0.2 and an embodied robot on house-a "
        "and house-b task episodes (about 3 minutes)",
    )
    bench.add_argument(
        "--households",
        action="store_true",
        help="only the CPU per household day of toyroom eval --days, batched (a household's days on one "
        "engine and one brain) against a process pair a run, on 2 households of 3 days (about 5 minutes)",
    )
    bench.add_argument(
        "--out", type=Path, default=Path("out/bench"), help="directory for bench.json and plots"
    )


def handle(args: argparse.Namespace) -> int:
    """``toyroom bench``: replace this process with ``python -m toyroom.bench`` and its flags."""
    flags = (["--quick"] if args.quick else []) + (["--memory"] if args.memory else [])
    flags += ["--households"] if args.households else []
    os.execv(sys.executable, [sys.executable, "-m", "toyroom.bench", *flags, "--out", str(args.out)])
    return 0  # pragma: no cover - execv does not return


COMMAND = Subcommand(
    "bench", "measure the transport, lock-step and brain speeds in one run", options, handle, out_folder=True
)
