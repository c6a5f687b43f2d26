"""The three person models on the same episode (engine core and tracker in one process)."""

from __future__ import annotations

import numpy as np
import pytest

from brain.tracking.tracker import MindTracker, Observer
from sim2d.engine import Engine


def follow(scenario: str, observer: Observer) -> MindTracker:
    engine = Engine(scenario)
    tracker = MindTracker(engine.scene(), observer=observer)
    tracker.observe(engine.state(), ())
    while not engine.done:
        result = engine.step()
        tracker.observe(result.state, result.events)
    return tracker


def test_percept_only_learns_nothing_about_preferences() -> None:
    tracker = follow("paper-2", Observer.PERCEPTONLY)
    for estimate in tracker.tracks["A1"].estimates:
        assert np.allclose(estimate.preference, 1 / 3), estimate.preference


@pytest.mark.parametrize("observer", list(Observer))
def test_every_observer_tracks_what_a1_saw_in_s1(observer: Observer) -> None:
    """Whatever the model, A1 standing in S1 at step 6 sees the ball there."""
    tracker = follow("paper-1", observer)
    tick = next(t for (t, agent), label in tracker.labels.items() if agent == "A1" and label == "6")
    track = tracker.tracks["A1"]
    i = max(j for j, s in enumerate(track.steps) if s.tick <= tick)
    ball = tracker.model.items.index("ball")
    s1 = tracker.model.locations.index("S1")
    assert track.estimates[i].beliefs[ball, s1] > 0.9
