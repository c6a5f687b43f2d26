"""``python -m toyroom.bench [--quick] [--out DIR]`` (what ``toyroom bench`` runs): every
performance number in one run; prints tables, writes ``DIR/bench.json``, ``DIR/perf.md``
and ``DIR/scaling.png``."""

from __future__ import annotations

import argparse
import sys
import tempfile
from collections.abc import Sequence
from pathlib import Path

from .suite import main as suite


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(
        prog="toyroom bench", description="toyroom's performance numbers, measured in one run."
    )
    parser.add_argument("--quick", action="store_true", help="fewer repeats and houses (under 3 minutes)")
    parser.add_argument("--out", type=Path, default=Path(tempfile.gettempdir()) / "toyroom-bench")
    args = parser.parse_args(argv)
    suite(args.quick, args.out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
