"""A lapse's row survives pruning until behaviour could show it: A1 overlooks the skate
(moved while they were out) when it comes into view, plays with the ball for a while, and
only then walks back to where they left the skate; the robot must flag the false belief
before they get there."""

from __future__ import annotations

from pathlib import Path

import pytest

import brain.model.person.lapses as lapses
from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from sim2d.engine import Engine

OVERLOOKED = """
name = "overlooked"
map = "paper"
description = "A1 overlooks the skate A2 moved to S2, plays with the ball, then walks to S1 for it."
robot = "observe"
tick_seconds = 0.1
max_ticks = 600
settle_ticks = 20

[[items]]
id = "skate"
shape = "board"
at = "S1"

[[items]]
id = "ball"
shape = "ball"
at = "P2"

[[agents]]
id = "A1"
kind = "person"
home = [5, 9]
script = [
  { do = "wait", ticks = 10 },
  { do = "enter", region = "O", label = "out" },
  { do = "wait", until = "A2:moved" },
  { do = "enter", region = "S2", label = "in-view" },
  { do = "goto", location = "P2" },
  { do = "take", item = "ball" },
  { do = "play", ticks = 120 },
  { do = "drop", label = "walks" },
  { do = "goto", location = "S1", label = "arrived" },
  { do = "wait" },
]

[[agents]]
id = "A2"
kind = "person"
home = [1, 9]
script = [
  { do = "wait", until = "A1:out" },
  { do = "goto", location = "S1" },
  { do = "take", item = "skate" },
  { do = "goto", location = "S2" },
  { do = "drop", label = "moved" },
  { do = "enter", region = "O" },
  { do = "wait" },
]

[[agents]]
id = "robot"
kind = "robot"
home = [7, 5]
"""


def walk_to_the_old_place(scenario: Path, miss: float) -> tuple[dict[str, int], list[float]]:
    """The ticks of A1's labelled steps and the robot's online P(A1 holds a false belief
    about the skate) at every tick."""
    engine = Engine(str(scenario))
    tracker = MindTracker(engine.scene(), ModelSettings(miss=miss))
    result = engine.reset()
    tracker.observe(result.state, result.events)
    skate = tracker.model.items.index("skate")
    p = [0.0]
    while not engine.done:
        result = engine.step()
        tracker.observe(result.state, result.events)
        estimate = tracker.online("A1")
        p.append(float(estimate.false_belief[skate]) if estimate is not None else 0.0)
    ticks = {label: tick for (tick, who), label in tracker.labels.items() if who == "A1"}
    return ticks, p


@pytest.fixture()
def scenario(tmp_path: Path) -> Path:
    path = tmp_path / "overlooked.toml"
    path.write_text(OVERLOOKED, encoding="utf-8")
    return path


@pytest.mark.parametrize("miss", [0.1, 0.2])
@pytest.mark.parametrize("crowded", [False, True], ids=["rows-to-spare", "crowded"])
def test_the_false_belief_is_flagged_before_they_arrive(
    scenario: Path, miss: float, crowded: bool, monkeypatch: pytest.MonkeyPatch
) -> None:
    """Crowded: room for one row only (as when other lapses and rumours fill the mixture):
    the overlooked row, lighter than the noticed one from its birth, is kept all the same
    while behaviour has not spoken against it."""
    if crowded:
        monkeypatch.setattr(lapses, "LAPSE_ROWS", 1)
    ticks, p = walk_to_the_old_place(scenario, miss)
    seen, walks, arrived = ticks["in-view"], ticks["walks"], ticks["arrived"]
    assert arrived - seen >= 150, f"the walk should come 150 ticks or more after the lapse: {ticks}"
    assert max(p[seen:walks]) < 0.5, f"nothing shows the lapse before the walk: {max(p[seen:walks]):.3f}"
    flagged = next((t for t in range(walks, arrived) if p[t] > 0.5), None)
    assert flagged is not None, f"P(false belief) stayed at {max(p[walks:arrived]):.3f} until A1 arrived"
    assert arrived - flagged >= 5, f"flagged at tick {flagged}, A1 arrived at {arrived}"


def test_without_lapses_nothing_is_flagged(scenario: Path) -> None:
    ticks, p = walk_to_the_old_place(scenario, 0.0)
    assert max(p[ticks["in-view"] :]) < 0.05, max(p[ticks["in-view"] :])
