"""Graded desires' planning time against one favourite's on the same map (issue 39): the
cold planner (every cache cleared, the person model built from scratch, as a brain process
does at its first state), repeated with the two interleaved, so both see the same machine.

    python bench/desire_planning.py [--map paper-2] [--repeats 9]

Prints each model's candidates and median seconds, and the ratio of medians with a
bootstrap 95% interval over the repeats (paired by repeat).
"""

from __future__ import annotations

import argparse
import statistics
import time

import numpy as np

from brain.model.desires import utilities
from brain.model.lookahead import cached_lookahead
from brain.model.personmodel import person_model
from brain.model.planner import cached_policy, rewards, transitions, use_store, value_iteration
from brain.model.world import build_world_model
from brain.settings import ModelSettings
from sim2d.engine import Engine


def cold_seconds(scene: object, settings: ModelSettings) -> float:
    """Seconds to build the person model of ``settings`` from empty caches."""
    use_store(None)  # clears the solved values and the policies
    cached_lookahead.cache_clear()
    start = time.perf_counter()
    person_model(scene, settings)  # type: ignore[arg-type]
    return time.perf_counter() - start


def iteration_seconds(scene: object, settings: ModelSettings) -> float:
    """Seconds of the per-candidate value iteration the planner used before issue 39 (one
    sweep loop per candidate, to ``vi_tolerance``), for comparison."""
    model = build_world_model(scene)  # type: ignore[arg-type]
    start = time.perf_counter()
    trans = transitions(model)
    for row in utilities(settings, model.n_items, leaves=bool(model.outside.any())):
        value_iteration(trans, rewards(model, trans, settings, row), settings.discount, settings.vi_tolerance)
    return time.perf_counter() - start


def main(map_name: str, repeats: int, seed: int = 0) -> dict[str, float]:
    """Median cold-planning seconds of each desire model and their ratio (graded / favourite)."""
    scene = Engine(map_name).scene()
    models = {name: ModelSettings(desire_model=name) for name in ("favourite", "graded")}
    times: dict[str, list[float]] = {name: [] for name in models}
    for settings in models.values():  # warm the imports and numpy's first calls, untimed
        cold_seconds(scene, settings)
    for _ in range(repeats):
        for name, settings in models.items():
            times[name].append(cold_seconds(scene, settings))
    fav, gra = np.array(times["favourite"]), np.array(times["graded"])
    rng = np.random.default_rng(seed)
    picks = rng.integers(0, repeats, size=(2000, repeats))
    boot = np.median(gra[picks], axis=1) / np.median(fav[picks], axis=1)
    ratio = float(np.median(gra) / np.median(fav))
    low, high = np.quantile(boot, [0.025, 0.975])
    for name in models:
        u = cached_policy(scene, models[name]).utilities
        print(
            f"{name:9s} {len(u):3d} candidates: median {statistics.median(times[name]):.3f} s "
            f"(min {min(times[name]):.3f}, max {max(times[name]):.3f})"
        )
    print(
        f"graded / favourite: {ratio:.2f}x (bootstrap 95% interval {low:.2f}-{high:.2f}, {repeats} repeats)"
    )
    old = {
        name: statistics.median(iteration_seconds(scene, models[name]) for _ in range(3)) for name in models
    }
    print(
        f"per-candidate value iteration (before): favourite {old['favourite']:.3f} s, graded "
        f"{old['graded']:.3f} s, {old['graded'] / old['favourite']:.2f}x (median of 3, planner only)"
    )
    return {"favourite_s": float(np.median(fav)), "graded_s": float(np.median(gra)), "ratio": ratio}


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--map", default="paper-2", help="a sim2d scenario whose map to plan on")
    parser.add_argument("--repeats", type=int, default=9)
    args = parser.parse_args()
    main(args.map, args.repeats)
