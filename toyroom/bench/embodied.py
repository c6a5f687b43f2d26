"""The households' row with an embodied robot (issue 66): the family's largest house (20
rooms, 10 items, 8 people), lapses on (``miss = 0.2``), followed by a robot that sees only
what its own cell sees (the factored unseen world, :mod:`brain.tracking.itemworld`) and,
beside it, by one that sees everything: the peak memory of each (the resident set's growth
over the process's, in GiB), the first look's time (the robot's first tick, where every
filter is made), and the tick's mean and 99th percentile (ms), against the targets.

    python -m toyroom.bench.embodied [--quick]
"""

from __future__ import annotations

import argparse
import resource
import statistics
import tempfile
import time
from pathlib import Path
from typing import Any

from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from protocol import EpisodeSpec, Perception, RobotMode
from sim2d.engine import Engine
from sim2d.generation import write_house_episode
from sim2d.scenario import load_scenario

from .scaling import FAMILY, HOUSEHOLD_TICK_MS, HOUSEHOLD_TICK_P99_MS, Ticks, percentile, record

PEAK_GIB = 2.0
FIRST_LOOK_S = 1.0
"""Targets of the embodied row (issue 66), besides the tick's (:data:`.scaling.HOUSEHOLD_TICK_MS`)."""


def peak_gib() -> float:
    """The process's peak resident memory so far (GiB; Linux counts kB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20


def run(engine: Engine, ticks: Ticks, settings: ModelSettings) -> dict[str, Any]:
    """One tracker over ``ticks``: the first look's seconds, each later tick's."""
    tracker = MindTracker(engine.scene(), settings)  # the planner, cached before: not timed
    (state, events), rest = ticks[0], ticks[1:]
    start = time.perf_counter()
    tracker.observe(state, events)
    first = time.perf_counter() - start
    per_tick = []
    for state, events in rest:
        start = time.perf_counter()
        tracker.observe(state, events)
        per_tick.append(time.perf_counter() - start)
    rows = {p: len(t.chains) for p, t in tracker.tracks.items()}
    return {
        "first_look_s": first,
        "tick_ms": statistics.mean(per_tick) * 1e3,
        "tick_p99_ms": percentile(per_tick, 0.99) * 1e3,
        "rows": max(rows.values()),
        "peak_gib": peak_gib(),
    }


def main(quick: bool = False, seed: int = 7) -> dict[str, Any]:
    """The row, omniscient first (its peak is the process's before the embodied run)."""
    rooms, items, people = FAMILY[-1]
    n = 200 if quick else 1000
    with tempfile.TemporaryDirectory(prefix="toyroom-embodied-") as tmp:
        path = write_house_episode(Path(tmp), rooms, items, seed, EpisodeSpec(max_ticks=n), people=people)
        engine = Engine(load_scenario(str(path)), robot=RobotMode.OBSERVE)
        ticks = record(engine, n)
    MindTracker(engine.scene(), ModelSettings(miss=0.2))  # the planner, into its cache
    omniscient = run(engine, ticks, ModelSettings(miss=0.2))
    embodied = run(engine, ticks, ModelSettings(miss=0.2, perception=Perception.EMBODIED))
    for name, row in (("omniscient", omniscient), ("embodied", embodied)):
        print(
            f"households embodied row ({rooms} rooms, {items} items, {people} people, miss 0.2, "
            f"{len(ticks)} ticks), {name}: peak {row['peak_gib']:.2f} GiB (target <= {PEAK_GIB:g}), "
            f"first look {row['first_look_s']:.2f} s (<= {FIRST_LOOK_S:g}), tick mean "
            f"{row['tick_ms']:.1f} ms (<= {HOUSEHOLD_TICK_MS:g}) and p99 {row['tick_p99_ms']:.1f} ms "
            f"(<= {HOUSEHOLD_TICK_P99_MS:g}); rows per person {row['rows']}"
        )
    return {"omniscient": omniscient, "embodied": embodied}


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    main(parser.parse_args().quick)
