"""The engine core's tick against another revision's, interleaved in one process.

This machine's speed drifts by up to 2x over seconds, so two timings taken one after the
other compare poorly; this runs ``sim2d`` as it is here and as it was at ``--against`` (its
files from git, imported under another name) side by side, in alternating blocks of ticks,
and prints the ratio of thread CPU time per tick (median over blocks, with the range of the
middle ones).

    python -m toyroom.bench.engine_ab --against REV [SCENARIO ...]   (default: paper-auto)

It needs a source checkout (git and the project's history).
"""

from __future__ import annotations

import argparse
import importlib
import io
import statistics
import subprocess
import sys
import tarfile
import tempfile
import time
from pathlib import Path
from typing import Any

from bridge.processes import CHECKOUT
from sim2d.engine import Engine


def other_engine(revision: str, folder: Path) -> Any:
    """``sim2d.engine.Engine`` as it was at ``revision`` (imported as ``sim2d_then``)."""
    archive = subprocess.run(
        ["git", "-C", str(CHECKOUT), "archive", revision, "sim2d"], capture_output=True, check=True
    ).stdout
    with tarfile.open(fileobj=io.BytesIO(archive)) as tar:
        tar.extractall(folder, filter="data")
    (folder / "sim2d").rename(folder / "sim2d_then")
    sys.path.insert(0, str(folder))
    return importlib.import_module("sim2d_then.engine").Engine


def ticks_per_block(engine: Any, ticks: int) -> float:
    """Thread CPU microseconds per tick over ``ticks`` ticks."""
    start = time.thread_time()
    for _ in range(ticks):
        engine.step()
    return (time.thread_time() - start) / ticks * 1e6


def compare(then: Any, now: Any, scenario: str, blocks: int = 20, ticks: int = 25) -> dict[str, float]:
    """Median microseconds per tick of each, and the ratio now / then per block pair."""
    a, b = then(scenario, seed=5), now(scenario, seed=5)
    for _ in range(50):
        a.step()
        b.step()
    old: list[float] = []
    new: list[float] = []
    for block in range(blocks):
        order = ((a, old), (b, new)) if block % 2 else ((b, new), (a, old))
        for engine, times in order:
            times.append(ticks_per_block(engine, ticks))
    ratios = sorted(n / o for o, n in zip(old, new, strict=True))
    return {
        "then_us": statistics.median(old),
        "now_us": statistics.median(new),
        "ratio": statistics.median(ratios),
        "ratio_lo": ratios[len(ratios) // 10],
        "ratio_hi": ratios[-1 - len(ratios) // 10],
    }


def main() -> None:
    """Print the comparison of each scenario asked for."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--against", required=True, help="a git revision (commit, tag, branch)")
    parser.add_argument("scenarios", nargs="*", default=["paper-auto"])
    args = parser.parse_args()
    with tempfile.TemporaryDirectory(prefix="toyroom-ab-") as folder:
        then = other_engine(args.against, Path(folder))
        for scenario in args.scenarios:
            r = compare(then, Engine, scenario)
            print(
                f"{scenario}: {args.against} {r['then_us']:.0f} us, now {r['now_us']:.0f} us per tick; "
                f"now / then {r['ratio']:.2f} [{r['ratio_lo']:.2f}, {r['ratio_hi']:.2f}]"
            )


if __name__ == "__main__":
    main()
