"""Desires as people read them on the food trucks' path types (issue 54): each scene of
``examples/food-trucks/`` run on sim2d in one process, the brain observing the student, and
the student's smoothed estimate after the clip's last step read as a rater is asked: each
truck's expected utility on the study's 1-7 scale (:func:`brain.model.desires.on_scale`)
and P(most wanted), beside the ordering people give (``examples/food-trucks/README.md``),
for one favourite (the default) and graded desires; and the log-evidence of the student's
path under each (the same defaults, nothing fitted to these paths).

One extra row, ``cut-short, on arrival``: the cut-short scene read at the tick the student
reaches the gap, before the 1 s stop: no decision has yet been made with the far spot in
view, so the Lebanese and the Mexican truck are exactly alike (docs/model.md, "Desires as
people read them").

    python studies/food_truck_paths.py [--set NAME=VALUE ...]
"""

from __future__ import annotations

import argparse
import dataclasses
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from brain.model.desires import on_scale
from brain.settings import ModelSettings, load_settings
from brain.tracking.tracker import MindTracker
from protocol import RobotMode
from sim2d.engine import Engine

SCENES = Path(__file__).resolve().parent.parent / "examples" / "food-trucks"
TRUCKS = ("korean", "lebanese", "mexican")
PATHS = (
    "check-and-go-back",
    "check-and-go-back-empty",
    "check-and-stay",
    "no-check",
    "no-check-empty",
    "cut-short",
    "cut-short-empty",
)


@dataclass(frozen=True)
class Reading:
    """The student's smoothed desires after the clip: ``(3,)`` each truck's expected utility
    on the 1-7 scale and ``(3,)`` P(most wanted) (Korean, Lebanese, Mexican), and the
    log-evidence of the path."""

    scale: np.ndarray
    most: np.ndarray
    log_evidence: float


GAP = (4, 1)
"""The gap in the wall, where both spots are in view."""


def read(path: str, settings: ModelSettings, on_arrival: bool = False) -> Reading:
    """Run the scene at ``path`` and read the student after the last step (``on_arrival``:
    after the tick the student first stands in the gap)."""
    engine = Engine(str(SCENES / f"{path}.toml"), robot=RobotMode.OBSERVE)
    tracker = MindTracker(engine.scene(), settings)
    tracker.observe(engine.state(), ())
    while not engine.done:
        result = engine.step()
        tracker.observe(result.state, result.events)
        student = next(a for a in result.state.agents if a.id == "student")
        if on_arrival and (student.cell.col, student.cell.row) == GAP:
            break
    est = tracker.smoothed("student")[-1]
    assert est.desire is not None
    index = [tracker.model.items.index(t) for t in TRUCKS]
    scale = on_scale(est.desire.utility, settings)[index]
    return Reading(scale, est.preference[index], tracker.tracks["student"].estimates[-1].log_evidence)


def pattern(path: str) -> str:
    """The ordering people give for a path type (the scene file's own comment)."""
    for line in (SCENES / f"{path}.toml").read_text().splitlines():
        if "The reading expected" in line:
            return line.split(": ", 1)[1].rstrip(".")
    return "-"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--set", action="append", default=[], metavar="NAME=VALUE")
    args = parser.parse_args()
    base = load_settings(None, args.set).model
    models = {
        m: dataclasses.replace(base, desire_model=d)
        for m, d in (("one favourite", "favourite"), ("graded", "graded"))
    }
    print("| path | people | model | E[u] K / L / M (1-7) | P(most wanted) K / L / M | log-evidence |")
    print("| --- | --- | --- | --- | --- | --- |")
    rows = [(p, False) for p in PATHS] + [("cut-short", True)]
    for path, on_arrival in rows:
        name = f"{path}, on arrival" if on_arrival else path
        for model, settings in models.items():
            r = read(path, settings, on_arrival)
            print(
                f"| {name} | {pattern(path)} | {model} | "
                + " / ".join(f"{x:.2f}" for x in r.scale)
                + " | "
                + " / ".join(f"{x:.2f}" for x in r.most)
                + f" | {r.log_evidence:.2f} |"
            )


if __name__ == "__main__":
    main()
