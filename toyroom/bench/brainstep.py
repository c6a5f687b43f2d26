"""Brain speed on the paper map: the planner's cold time and the online update per person
per tick, on a recorded paper-2 episode (the engine core runs first, untimed), for the
graded model (the default) and the paper's point beliefs side by side.

    python -m toyroom.bench.brainstep [--repeats N]
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from rich.console import Console
from rich.table import Table

from brain.model.lookahead import cached_lookahead
from brain.model.person.personmodel import person_model
from brain.model.planner import cached_policy
from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from protocol import Event, RobotMode, Scene, State
from sim2d.engine import Engine
from sim2d.generation import write_episode
from sim2d.scenario import load_scenario


def timed_observe(tracker: MindTracker, state: State, events: Sequence[Event]) -> float | None:
    """Feed one tick; the seconds it took per person-step, or ``None`` when nobody stepped."""
    before = sum(len(t.steps) for t in tracker.tracks.values())
    start = time.perf_counter()
    tracker.observe(state, events)
    elapsed = time.perf_counter() - start
    stepped = sum(len(t.steps) for t in tracker.tracks.values()) - before
    return elapsed / stepped if stepped else None


def nested_timer(tracker: MindTracker) -> list[float]:
    """Time ``tracker``'s nested beliefs from now on: the returned list gets the seconds of
    each of their updates (one per tick the tracker observes), so that a tick's first-order
    time is its whole time less its entry."""
    spent: list[float] = []
    observe = tracker.nested.observe

    def timed(*args: Any) -> None:
        start = time.perf_counter()
        observe(*args)
        spent.append(time.perf_counter() - start)

    setattr(tracker.nested, observe.__name__, timed)  # noqa: B010 (mypy refuses a method assigned)
    return spent


def measure(
    scene: Scene, ticks: list[tuple[State, tuple[Event, ...]]], settings: ModelSettings, repeats: int
) -> dict[str, float]:
    """Planner cold time (s; the person model built from an empty cache) and the online
    step per person (us, median and p99) of one model."""
    cold = []
    for _ in range(repeats):
        cached_policy.cache_clear()
        cached_lookahead.cache_clear()
        start = time.perf_counter()
        person_model(scene, settings)
        cold.append(time.perf_counter() - start)
    per_step: list[float] = []
    nested: list[float] = []
    total = 0.0
    for _ in range(repeats):
        tracker = MindTracker(scene, settings)
        spent = nested_timer(tracker)
        start = time.perf_counter()
        for state, events in ticks:
            elapsed = timed_observe(tracker, state, events)
            if elapsed is not None:
                per_step.append(elapsed)
        total += time.perf_counter() - start
        nested.extend(spent)
    per_step.sort()
    return {
        "planner_cold_s": statistics.median(cold),
        "brain_step_us_median": statistics.median(per_step) * 1e6,
        "brain_step_us_p99": per_step[int(0.99 * (len(per_step) - 1))] * 1e6,
        "nested_ratio": total / max(total - sum(nested), 1e-12),
    }


def houses(ticks: int = 300) -> dict[str, float]:
    """The tracker's time per tick (ms, all people, engine excluded) of each model on the
    evaluation's two generated houses (``W = 512``), ``ticks`` ticks of one episode each."""
    out: dict[str, float] = {}
    with tempfile.TemporaryDirectory() as tmp:
        for map_name, seed in (("house-a", 5), ("house-b", 7)):
            scenario = load_scenario(str(write_episode(Path(tmp), map_name, seed)))
            engine = Engine(scenario, robot=RobotMode.OBSERVE)
            stream: list[tuple[State, tuple[Event, ...]]] = [(engine.state(), ())]
            while not engine.done and len(stream) <= ticks:
                result = engine.step()
                stream.append((result.state, result.events))
            for model in ("point", "graded"):
                tracker = MindTracker(engine.scene(), ModelSettings(belief_model=model))
                start = time.perf_counter()
                for state, events in stream:
                    tracker.observe(state, events)
                out[f"{map_name}_{model}_tick_ms"] = (time.perf_counter() - start) / len(stream) * 1e3
    return out


def main(repeats: int = 5) -> dict[str, float]:
    """Every model's numbers on paper-2 and the houses, printed as tables (times in the
    units their names say)."""
    engine = Engine("paper-2")
    ticks: list[tuple[State, tuple[Event, ...]]] = [(engine.state(), ())]
    while not engine.done:
        result = engine.step()
        ticks.append((result.state, result.events))
    scene = engine.scene()
    numbers = measure(scene, ticks, ModelSettings(belief_model="point"), repeats)
    graded = measure(scene, ticks, ModelSettings(belief_model="graded"), repeats)
    numbers |= {f"graded_{name}": value for name, value in graded.items()}
    desires = measure(scene, ticks, ModelSettings(belief_model="graded", desire_model="graded"), repeats)
    numbers |= {f"graded_desires_{name}": value for name, value in desires.items()}
    looking = measure(scene, ticks, ModelSettings(belief_model="graded", person_planner="belief"), repeats)
    numbers |= {f"graded_lookahead_{name}": value for name, value in looking.items()}
    table = Table(title=f"brain on the paper map ({repeats} repeats, {len(ticks)} ticks of paper-2)")
    table.add_column("measure", no_wrap=True)
    table.add_column("point", justify="right")
    table.add_column("graded (default)", justify="right")
    table.add_column("graded desires", justify="right")
    table.add_column("belief-space", justify="right")
    table.add_column("target", justify="right")
    table.add_row(
        "planner, cold (s)",
        f"{numbers['planner_cold_s']:.3f}",
        f"{graded['planner_cold_s']:.3f}",
        f"{desires['planner_cold_s']:.3f}",
        f"{looking['planner_cold_s']:.3f}",
        "<= 0.5 / 2",
    )
    for name, label, target in (
        ("brain_step_us_median", "online step per person, median (us)", "<= 1000"),
        ("brain_step_us_p99", "online step per person, p99 (us)", ""),
    ):
        table.add_row(
            label,
            f"{numbers[name]:.0f}",
            f"{graded[name]:.0f}",
            f"{desires[name]:.0f}",
            f"{looking[name]:.0f}",
            target,
        )
    table.add_row(
        "all ticks with nested beliefs / without (x)",
        f"{numbers['nested_ratio']:.2f}",
        f"{graded['nested_ratio']:.2f}",
        f"{desires['nested_ratio']:.2f}",
        f"{looking['nested_ratio']:.2f}",
        "<= 2",
    )
    Console(width=140).print(table)
    house = houses()
    numbers |= house
    table = Table(title="the tracker per tick on the evaluation houses (W = 512; 300 ticks, all people)")
    table.add_column("house")
    table.add_column("point (ms)", justify="right")
    table.add_column("graded (ms)", justify="right")
    for map_name in ("house-a", "house-b"):
        table.add_row(
            map_name,
            f"{house[f'{map_name}_point_tick_ms']:.2f}",
            f"{house[f'{map_name}_graded_tick_ms']:.2f}",
        )
    Console().print(table)
    return numbers


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=5)
    main(parser.parse_args().repeats)
