"""The graded and the point belief model side by side on the paper's Section V: the numbers
``docs/model.md`` quotes, including the statements REVIEW section 3 found unasserted.

Each scenario is played by the engine core (the robot only observes) and followed by a
tracker of each model (``belief_model = graded | point``, every other setting the default,
or ``--set NAME=VALUE`` for both). Smoothed estimates unless a row says ``online``.

    python studies/compare_models.py [--set NAME=VALUE ...] [--json FILE]
"""

from __future__ import annotations

import argparse
import dataclasses
import json
from collections.abc import Callable
from pathlib import Path

import numpy as np
from rich.console import Console
from rich.table import Table

from brain.model.estimates import Estimate, false_belief_probability
from brain.settings import ModelSettings, load_settings
from brain.tracking.tracker import MindTracker
from protocol import RobotMode
from sim2d.engine import Engine

MODELS = ("graded", "point")


@dataclasses.dataclass
class Run:
    """One scenario followed by one model: estimates by (person, label)."""

    tracker: MindTracker
    smoothed: dict[str, list[Estimate]]

    def label_tick(self, person: str, label: str) -> int:
        ticks = [tick for (tick, who), name in self.tracker.labels.items() if who == person and name == label]
        if not ticks:
            raise KeyError(f"no step '{label}' of {person}")
        return ticks[0]

    def at(self, person: str, label: str, online: bool = False, tick: int | None = None) -> Estimate:
        """The estimate after the last of ``person``'s steps at or before step ``label`` (or
        ``tick``)."""
        tick = self.label_tick(person, label) if tick is None else tick
        track = self.tracker.tracks[person]
        index = max(i for i, step in enumerate(track.steps) if step.tick <= tick)
        return track.estimates[index] if online else self.smoothed[person][index]

    def false_belief(self, person: str, label: str, item: str, by: str | None = None) -> float:
        """The online P(false belief) about ``item`` against the truth at ``person``'s step
        ``label`` (or at step ``label`` of ``by``)."""
        tracker = self.tracker
        tick = self.label_tick(by or person, label)
        est = self.at(person, label, online=True, tick=tick)
        p = false_belief_probability(est, tracker.truths[tick], tracker.settings.false_belief_mass)
        return float(p[tracker.model.items.index(item)])

    def belief(self, person: str, label: str, item: str, location: str) -> float:
        model = self.tracker.model
        est = self.at(person, label)
        return float(est.beliefs[model.items.index(item), model.locations.index(location)])

    def preference(self, person: str, label: str, goal: str) -> float:
        names = [*self.tracker.model.items, "out"]
        return float(self.at(person, label).preference[names.index(goal)])

    def preferred(self, person: str, label: str, goal: str, over: str) -> float:
        """P(``goal`` is worth more to the person than ``over``)."""
        names = [*self.tracker.model.items, "out"]
        desire = self.at(person, label).desire
        return float(desire.preferred[names.index(goal), names.index(over)]) if desire else float("nan")

    def unsure(self, person: str, label: str, item: str, a: str, b: str) -> float:
        """P(the person's own belief gives both ``a`` and ``b`` at least 0.25 for ``item``):
        their own uncertainty (0 for point beliefs, where each person is certain)."""
        est = self.at(person, label)
        if est.hypotheses is None:
            return 0.0
        model = self.tracker.model
        weights, own = est.hypotheses
        k = model.items.index(item)
        both = (own[:, k, model.locations.index(a)] >= 0.25) & (own[:, k, model.locations.index(b)] >= 0.25)
        return float(weights @ both)


def follow(scenario: str, settings: ModelSettings) -> Run:
    engine = Engine(scenario, robot=RobotMode.OBSERVE)
    tracker = MindTracker(engine.scene(), settings)
    tracker.observe(engine.state(), ())
    while not engine.done:
        result = engine.step()
        tracker.observe(result.state, result.events)
    return Run(tracker, {person: tracker.smoothed(person) for person in tracker.people})


Row = tuple[str, str, Callable[[dict[str, Run]], float]]

ROWS: list[Row] = [
    ("S1 steps 0-2: P(false belief about the ball), online, max", "< 0.2 graded",
     lambda r: max(r["paper-1"].false_belief("A1", s, "ball") for s in "012")),
    ("S1 step 5: P(false belief about the ball), online", "> 0.8",
     lambda r: r["paper-1"].false_belief("A1", "5", "ball")),
    ("S1 step 2: P(A1 herself unsure: ball S2 and P2 >= 0.25 each)", "high graded",
     lambda r: r["paper-1"].unsure("A1", "2", "ball", "S2", "P2")),
    ("S1 step 2: P(ball in S2) / P(ball in P2)", "neither > 0.9",
     lambda r: r["paper-1"].belief("A1", "2", "ball", "S2")),
    ("", "",
     lambda r: r["paper-1"].belief("A1", "2", "ball", "P2")),
    ("S1 step 2: preference ball / skate / out", "paper: ball early",
     lambda r: r["paper-1"].preference("A1", "2", "ball")),
    ("", "", lambda r: r["paper-1"].preference("A1", "2", "skate")),
    ("", "", lambda r: r["paper-1"].preference("A1", "2", "out")),
    ("S1 step 6: P(skate in P2)", "truth 0.5",
     lambda r: r["paper-1"].belief("A1", "6", "skate", "P2")),
    ("S3 step 6: P(ball in S1) / P(ball in P1)", "paper: S1 already",
     lambda r: r["paper-3"].belief("A1", "6", "ball", "S1")),
    ("", "", lambda r: r["paper-3"].belief("A1", "6", "ball", "P1")),
    ("S2 step 8: preference ball / skate", "paper: lags",
     lambda r: r["paper-2"].preference("A1", "8", "ball")),
    ("", "", lambda r: r["paper-2"].preference("A1", "8", "skate")),
    ("S2 step 9: preference ball / skate", "ball > skate",
     lambda r: r["paper-2"].preference("A1", "9", "ball")),
    ("", "", lambda r: r["paper-2"].preference("A1", "9", "skate")),
    ("S1 step 6: P(ball preferred to leaving)", "low: she leaves",
     lambda r: r["paper-1"].preferred("A1", "6", "ball", "out")),
    ("S2 step 6: P(ball preferred to leaving)", "high, graded desires",
     lambda r: r["paper-2"].preferred("A1", "6", "ball", "out")),
    ("Sally-Anne, after the move: P(Sally's false belief), online", "> 0.8",
     lambda r: r["sally-anne"].false_belief("sally", "moved", "marble", by="anne")),
    ("Sally-Anne, after the move: P(Anne's false belief), online", "< 0.2",
     lambda r: r["sally-anne"].false_belief("anne", "moved", "marble")),
]  # fmt: skip


def main(overrides: list[str], json_path: Path | None) -> dict[str, list[float]]:
    base = load_settings(None, overrides).model
    runs = {
        model: {
            name: follow(name, dataclasses.replace(base, belief_model=model))
            for name in ("paper-1", "paper-2", "paper-3", "sally-anne")
        }
        for model in MODELS
    }
    table = Table(title="graded against point beliefs on Section V (smoothed unless online)")
    for column in ("quantity", "expected", *MODELS):
        table.add_column(column, justify="left" if column in ("quantity", "expected") else "right")
    out: dict[str, list[float]] = {}
    label = ""
    for name, expected, read in ROWS:
        label = name or label
        values = [read(runs[model]) for model in MODELS]
        out.setdefault(label, []).append(values[0])
        out[label].append(values[1])
        table.add_row(name, expected, *(f"{v:.2f}" for v in values))
    Console().print(table)
    if json_path is not None:
        json_path.write_text(json.dumps({"models": MODELS, "rows": out}, indent=2) + "\n")
    return out


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--set", action="append", default=[], metavar="NAME=VALUE")
    parser.add_argument("--json", type=Path, default=None)
    args = parser.parse_args()
    np.set_printoptions(precision=3)
    main(args.set, args.json)
