"""The brain on a family of generated houses, and the factored model against the exact one.

For each house of the family (``toyroom generate --rooms R --items K``, one item
spot per room), an episode of autonomous people is recorded with the engine core, then fed
to the brain with point beliefs (``belief_model = "point"``: exact below
``ModelSettings.exact_max_worlds``, factored above; the graded default uses the factored
model above it too): ``planner_s`` (cold), ``step_us`` (median online update per person per
step; ``step_p99_us``). Wherever the exact model still fits (``W <= EXACT_FITS``), both
models also run on the same ticks and ``tv_vs_exact`` is the mean total-variation distance
between their item beliefs per person, item and tick (``preference_tv_vs_exact`` the same
for preferences); elsewhere those are ``null``. ``paper`` does the same on the paper map's
scenarios.

    python -m toyroom.bench.scaling [--quick | --households]

``--households`` runs the last house of the family alone (20 rooms, 10 items, 8 people, 1000
ticks) and prints its tick with and without the nested beliefs against the target.
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
import tracemalloc
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from rich.console import Console
from rich.table import Table

from brain.model.factored import cached_factored_policy
from brain.model.planner import cached_policy
from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from protocol import EpisodeSpec, Event, RobotMode, State
from sim2d.engine import Engine
from sim2d.generation import write_house_episode
from sim2d.scenario import load_scenario

from .brainstep import nested_timer, timed_observe

FAMILY = ((4, 2, 2), (5, 3, 2), (6, 3, 2), (8, 4, 2), (10, 6, 2), (12, 6, 2), (16, 8, 6), (20, 10, 8))
"""(rooms, items, people) of the generated houses, smallest first: the last, households of
up to eight (target: at most ``HOUSEHOLD_TICK_MS`` per tick for all people together)."""
QUICK_FAMILY = ((4, 2, 2), (5, 3, 2), (8, 4, 2), (10, 6, 2), (20, 10, 8))
HOUSEHOLD_TICK_MS = 20.0
HOUSEHOLD_TICK_P99_MS = 50.0
"""Households: the mean and the 99th percentile of a tick, all people and their nested beliefs
about each other together (issue 57)."""
EXACT_FITS = 2000
"""The largest ``W`` for which the benchmark also runs the exact model (its planner takes
seconds and its step tens of milliseconds there; beyond, it does not fit in memory)."""
GRADED_EXACT_FITS = 512
"""The same for the exact graded model (its ``G`` hypotheses times ``W`` worlds)."""
PAPER_SCENARIOS = ("paper-1", "paper-2", "paper-3", "paper-robot", "paper-auto")

Ticks = list[tuple[State, tuple[Event, ...]]]


def record(engine: Engine, max_ticks: int) -> Ticks:
    """The engine core's ticks (state and events), with the robot observing."""
    ticks: Ticks = [(engine.state(), ())]
    while not engine.done and len(ticks) <= max_ticks:
        result = engine.step()
        ticks.append((result.state, result.events))
    return ticks


@dataclass
class Followed:
    """A tracker that followed an episode, and what it took."""

    tracker: MindTracker
    planner_s: float
    """The person model built from a cold cache."""
    per_step: list[float]
    """Seconds per person-step, each tick where someone stepped."""
    per_tick: list[float]
    """Seconds per tick, all people together (nobody stepping included)."""
    first_order: list[float]
    """The same less the nested beliefs' update (what each person believes alone)."""


def follow(engine: Engine, ticks: Ticks, settings: ModelSettings) -> Followed:
    """A tracker over ``ticks`` from a cold cache."""
    cached_policy.cache_clear()
    cached_factored_policy.cache_clear()
    start = time.perf_counter()
    tracker = MindTracker(engine.scene(), settings)
    planner = time.perf_counter() - start
    nested = nested_timer(tracker)
    per_step, per_tick, first_order = [], [], []
    for state, events in ticks:
        started, before = time.perf_counter(), len(nested)
        elapsed = timed_observe(tracker, state, events)
        per_tick.append(time.perf_counter() - started)
        first_order.append(per_tick[-1] - sum(nested[before:]))
        if elapsed is not None:
            per_step.append(elapsed)
    return Followed(tracker, planner, per_step, per_tick, first_order)


def memory_per_person(engine: Engine, ticks: Ticks, settings: ModelSettings) -> float:
    """Bytes a tracker holds per person after ``ticks`` (its filters and the records its
    smoother needs; the planner, shared by everyone, is cached before and not counted)."""
    MindTracker(engine.scene(), settings)  # the planner, into its cache
    tracemalloc.start()
    try:
        before = tracemalloc.get_traced_memory()[0]
        tracker = MindTracker(engine.scene(), settings)
        for state, events in ticks:
            tracker.observe(state, events)
        held = tracemalloc.get_traced_memory()[0] - before
    finally:
        tracemalloc.stop()
    return held / max(1, len(tracker.people))


def smoothing(tracker: MindTracker) -> float:
    """Seconds to smooth every person's whole episode."""
    start = time.perf_counter()
    for person in tracker.people:
        tracker.smoothed(person)
    return time.perf_counter() - start


def divergence(engine: Engine, ticks: Ticks, belief_model: str = "point") -> dict[str, float]:
    """Mean TV distance between the factored and exact models' online item beliefs, and
    between their preferences, per person, item and tick (both with ``belief_model``); and
    the exact model's cold planner time and median step time on these ticks."""
    cached_policy.cache_clear()
    start = time.perf_counter()
    exact = MindTracker(engine.scene(), ModelSettings(belief_model=belief_model, exact_max_worlds=1 << 62))
    planner = time.perf_counter() - start
    factored = MindTracker(engine.scene(), ModelSettings(belief_model=belief_model, exact_max_worlds=0))
    beliefs, preferences, per_step = [], [], []
    for state, events in ticks:
        elapsed = timed_observe(exact, state, events)
        if elapsed is not None:
            per_step.append(elapsed)
        factored.observe(state, events)
        for person in exact.people:
            a, b = exact.online(person), factored.online(person)
            if a is None or b is None:
                continue
            beliefs.extend(0.5 * np.abs(a.beliefs - b.beliefs).sum(axis=1))
            preferences.append(0.5 * float(np.abs(a.preference - b.preference).sum()))
    smoothed_beliefs, smoothed_preferences = [], []
    for person in exact.people:
        for a, b in zip(exact.smoothed(person), factored.smoothed(person), strict=True):
            smoothed_beliefs.extend(0.5 * np.abs(a.beliefs - b.beliefs).sum(axis=1))
            smoothed_preferences.append(0.5 * float(np.abs(a.preference - b.preference).sum()))
    return {
        "tv_vs_exact": float(np.mean(beliefs)),
        "preference_tv_vs_exact": float(np.mean(preferences)),
        "smoothed_tv_vs_exact": float(np.mean(smoothed_beliefs)),
        "smoothed_preference_tv_vs_exact": float(np.mean(smoothed_preferences)),
        "exact_planner_s": planner,
        "exact_step_us": statistics.median(per_step) * 1e6,
    }


def percentile(values: list[float], q: float) -> float:
    """The ``q`` quantile of ``values`` (the nearest rank below)."""
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(q * (len(ordered) - 1)))]


def house(rooms: int, items: int, people: int, ticks: int, directory: Path, seed: int = 7) -> dict[str, Any]:
    """Every number of one house of the family."""
    path = write_house_episode(directory, rooms, items, seed, EpisodeSpec(max_ticks=ticks), people=people)
    engine = Engine(load_scenario(str(path)), robot=RobotMode.OBSERVE)
    recorded = record(engine, ticks)
    point = follow(engine, recorded, ModelSettings(belief_model="point"))
    model = point.tracker.model
    row: dict[str, Any] = {
        "rooms": rooms,
        "items": items,
        "people": len(point.tracker.people),
        "locations": model.n_locations,
        "cells": model.n_cells,
        "worlds": model.n_worlds,
        "exact": point.tracker.exact,
        "planner_s": point.planner_s,
        "step_us": statistics.median(point.per_step) * 1e6,
        "step_p99_us": percentile(point.per_step, 0.99) * 1e6,
        "steps": len(point.per_step),
        "tv_vs_exact": None,
        "preference_tv_vs_exact": None,
        "exact_planner_s": None,
        "exact_step_us": None,
    }
    smoothed: dict[str, Any] = dict.fromkeys(("tv_vs_exact", "preference_tv_vs_exact", "point_tv_vs_exact"))
    if model.n_worlds <= EXACT_FITS:
        numbers = divergence(engine, recorded)
        smoothed["point_tv_vs_exact"] = numbers.pop("smoothed_tv_vs_exact")
        numbers.pop("smoothed_preference_tv_vs_exact")
        row.update(numbers)
    graded = follow(engine, recorded, ModelSettings())
    smoothed["seconds"] = smoothing(graded.tracker)
    row |= {
        "graded_planner_s": graded.planner_s,
        "graded_step_us": statistics.median(graded.per_step) * 1e6,
        "graded_step_p99_us": percentile(graded.per_step, 0.99) * 1e6,
        "tick_us": statistics.mean(graded.per_tick) * 1e6,
        "tick_median_us": statistics.median(graded.per_tick) * 1e6,
        "tick_p99_us": percentile(graded.per_tick, 0.99) * 1e6,
        "nested_pairs": len(graded.tracker.nested.pairs),
        "first_order_tick_us": statistics.mean(graded.first_order) * 1e6,
        "first_order_tick_p99_us": percentile(graded.first_order, 0.99) * 1e6,
        "memory_per_person_bytes": memory_per_person(engine, recorded, ModelSettings()),
        "graded_tv_vs_exact": None,
        "graded_preference_tv_vs_exact": None,
        "smoothed": smoothed,
    }
    if model.n_worlds <= GRADED_EXACT_FITS:
        numbers = divergence(engine, recorded, "graded")
        row |= {
            "graded_tv_vs_exact": numbers["tv_vs_exact"],
            "graded_preference_tv_vs_exact": numbers["preference_tv_vs_exact"],
        }
        smoothed["tv_vs_exact"] = numbers["smoothed_tv_vs_exact"]
        smoothed["preference_tv_vs_exact"] = numbers["smoothed_preference_tv_vs_exact"]
    return row


def paper(ticks: int) -> dict[str, dict[str, float]]:
    """``tv_vs_exact`` on the paper map's scenarios."""
    out = {}
    for name in PAPER_SCENARIOS:
        engine = Engine(name, robot=RobotMode.OBSERVE)
        recorded = record(engine, ticks)
        numbers = divergence(engine, recorded)
        graded = divergence(engine, recorded, "graded")
        kept: tuple[str, ...] = ("tv_vs_exact", "preference_tv_vs_exact")
        kept += tuple(f"smoothed_{k}" for k in kept)
        out[name] = {k: numbers[k] for k in kept} | {f"graded_{k}": graded[k] for k in kept}
    return out


def households_line(row: dict[str, Any]) -> str:
    """The households' tick with nested beliefs against the target, beside the first-order one."""
    keys = ("tick_us", "tick_p99_us", "first_order_tick_us", "first_order_tick_p99_us")
    ms = {k: row[k] / 1e3 for k in keys}
    return (
        f"households ({row['rooms']} rooms, {row['items']} items, {row['people']} people, "
        f"{row['nested_pairs']} ordered pairs): per tick, mean {ms['tick_us']:.1f} ms and p99 "
        f"{ms['tick_p99_us']:.1f} ms with nested beliefs (target <= {HOUSEHOLD_TICK_MS:g} and "
        f"<= {HOUSEHOLD_TICK_P99_MS:g}); first-order alone {ms['first_order_tick_us']:.1f} ms and "
        f"{ms['first_order_tick_p99_us']:.1f} ms"
    )


def main(quick: bool = False) -> dict[str, Any]:
    """The family's rows and the paper map's TVs, printed as a table."""
    ticks = 400 if quick else 1000
    family = QUICK_FAMILY if quick else FAMILY
    with tempfile.TemporaryDirectory(prefix="toyroom-scaling-") as tmp:
        rows = [house(rooms, items, people, ticks, Path(tmp)) for rooms, items, people in family]
    numbers: dict[str, Any] = {"scaling": rows, "paper_tv_vs_exact": paper(ticks)}
    table = Table(
        title=f"the brain on generated houses ({ticks} ticks each; factored above W = "
        f"{ModelSettings().exact_max_worlds})"
    )
    columns = ("rooms", "items", "worlds", "model", "planner s", "step us (p99)", "exact: planner s, step us")
    more = ("tv vs exact", "graded step us", "graded tv", "people", "tick ms (p99)", "smoothed tv")
    for column in (*columns, *more):
        table.add_column(column, justify="right")
    for r in rows:
        tv = "-" if r["tv_vs_exact"] is None else f"{r['tv_vs_exact']:.4f}"
        table.add_row(
            str(r["rooms"]),
            str(r["items"]),
            f"{r['worlds']:.3g}",
            "exact" if r["exact"] else "factored",
            f"{r['planner_s']:.2f}",
            f"{r['step_us']:.0f} ({r['step_p99_us']:.0f})",
            "-" if r["exact_step_us"] is None else f"{r['exact_planner_s']:.2f}, {r['exact_step_us']:.0f}",
            tv,
            f"{r['graded_step_us']:.0f}",
            "-" if r["graded_tv_vs_exact"] is None else f"{r['graded_tv_vs_exact']:.4f}",
            str(r["people"]),
            f"{r['tick_us'] / 1e3:.1f} ({r['tick_p99_us'] / 1e3:.1f})",
            "-" if r["smoothed"]["tv_vs_exact"] is None else f"{r['smoothed']['tv_vs_exact']:.4f}",
        )
    Console(width=200).print(table)
    print(households_line(rows[-1]))
    for name, v in numbers["paper_tv_vs_exact"].items():
        print(
            f"{name}: tv_vs_exact {v['tv_vs_exact']:.4f}, preferences {v['preference_tv_vs_exact']:.4f}; "
            f"graded: {v['graded_tv_vs_exact']:.4f}, preferences {v['graded_preference_tv_vs_exact']:.4f}; "
            f"smoothed {v['smoothed_tv_vs_exact']:.4f}, graded {v['graded_smoothed_tv_vs_exact']:.4f}"
        )
    return numbers


def households(ticks: int = 1000) -> dict[str, Any]:
    """The households' row alone (the family's last house), its line printed."""
    rooms, items, people = FAMILY[-1]
    with tempfile.TemporaryDirectory(prefix="toyroom-households-") as tmp:
        row = house(rooms, items, people, ticks, Path(tmp))
    print(households_line(row))
    return row


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--households", action="store_true", help="the households' row alone")
    args = parser.parse_args()
    if args.households:
        households()
    else:
        main(args.quick)
