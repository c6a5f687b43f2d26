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

    python bench/scaling.py [--quick]
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np
from brain_bench import timed_observe
from rich.console import Console
from rich.table import Table

from brain.model.factored import cached_factored_policy
from brain.model.planner import cached_policy
from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from protocol import Event, State
from sim2d.engine import Engine
from sim2d.generate import write_house_episode
from sim2d.scenario import load_scenario

FAMILY = ((4, 2), (5, 3), (6, 3), (8, 4), (10, 6), (12, 6))
"""(rooms, items) of the generated houses, smallest first."""
QUICK_FAMILY = ((4, 2), (5, 3), (8, 4), (10, 6))
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


def follow(engine: Engine, ticks: Ticks, settings: ModelSettings) -> tuple[MindTracker, float, list[float]]:
    """A tracker over ``ticks`` from a cold cache: (tracker, planner seconds, seconds per person-step)."""
    cached_policy.cache_clear()
    cached_factored_policy.cache_clear()
    start = time.perf_counter()
    tracker = MindTracker(engine.scene(), settings)
    planner = time.perf_counter() - start
    per_step = [t for t in (timed_observe(tracker, s, e) for s, e in ticks) if t is not None]
    return tracker, planner, per_step


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
    return {
        "tv_vs_exact": float(np.mean(beliefs)),
        "preference_tv_vs_exact": float(np.mean(preferences)),
        "exact_planner_s": planner,
        "exact_step_us": statistics.median(per_step) * 1e6,
    }


def percentile(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(q * (len(ordered) - 1)))]


def house(rooms: int, items: int, ticks: int, directory: Path, seed: int = 7) -> dict[str, Any]:
    """Every number of one house of the family."""
    path = write_house_episode(directory, rooms, items, seed, max_ticks=ticks)
    engine = Engine(load_scenario(str(path)), robot="observe")
    recorded = record(engine, ticks)
    tracker, planner, per_step = follow(engine, recorded, ModelSettings(belief_model="point"))
    model = tracker.model
    row: dict[str, Any] = {
        "rooms": rooms,
        "items": items,
        "locations": model.n_locations,
        "cells": model.n_cells,
        "worlds": model.n_worlds,
        "exact": tracker.exact,
        "planner_s": planner,
        "step_us": statistics.median(per_step) * 1e6,
        "step_p99_us": percentile(per_step, 0.99) * 1e6,
        "steps": len(per_step),
        "tv_vs_exact": None,
        "preference_tv_vs_exact": None,
        "exact_planner_s": None,
        "exact_step_us": None,
    }
    if model.n_worlds <= EXACT_FITS:
        row.update(divergence(engine, recorded))
    _, graded_planner, graded_steps = follow(engine, recorded, ModelSettings())
    row |= {
        "graded_planner_s": graded_planner,
        "graded_step_us": statistics.median(graded_steps) * 1e6,
        "graded_step_p99_us": percentile(graded_steps, 0.99) * 1e6,
        "graded_tv_vs_exact": None,
        "graded_preference_tv_vs_exact": None,
    }
    if model.n_worlds <= GRADED_EXACT_FITS:
        graded = divergence(engine, recorded, "graded")
        row |= {
            "graded_tv_vs_exact": graded["tv_vs_exact"],
            "graded_preference_tv_vs_exact": graded["preference_tv_vs_exact"],
        }
    return row


def paper(ticks: int) -> dict[str, dict[str, float]]:
    """``tv_vs_exact`` on the paper map's scenarios."""
    out = {}
    for name in PAPER_SCENARIOS:
        engine = Engine(name, robot="observe")
        recorded = record(engine, ticks)
        numbers = divergence(engine, recorded)
        graded = divergence(engine, recorded, "graded")
        out[name] = {k: numbers[k] for k in ("tv_vs_exact", "preference_tv_vs_exact")} | {
            "graded_tv_vs_exact": graded["tv_vs_exact"],
            "graded_preference_tv_vs_exact": graded["preference_tv_vs_exact"],
        }
    return out


def main(quick: bool = False) -> dict[str, Any]:
    ticks = 400 if quick else 1000
    family = QUICK_FAMILY if quick else FAMILY
    with tempfile.TemporaryDirectory(prefix="toyroom-scaling-") as tmp:
        rows = [house(rooms, items, ticks, Path(tmp)) for rooms, items in family]
    numbers = {"scaling": rows, "paper_tv_vs_exact": paper(ticks)}
    table = Table(
        title=f"the brain on generated houses ({ticks} ticks each; factored above W = "
        f"{ModelSettings().exact_max_worlds})"
    )
    columns = ("rooms", "items", "worlds", "model", "planner s", "step us (p99)", "exact: planner s, step us")
    for column in (*columns, "tv vs exact", "graded step us", "graded tv"):
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
        )
    Console(width=160).print(table)
    for name, v in numbers["paper_tv_vs_exact"].items():
        print(
            f"{name}: tv_vs_exact {v['tv_vs_exact']:.4f}, preferences {v['preference_tv_vs_exact']:.4f}; "
            f"graded: {v['graded_tv_vs_exact']:.4f}, preferences {v['graded_preference_tv_vs_exact']:.4f}"
        )
    return numbers


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    main(parser.parse_args().quick)
