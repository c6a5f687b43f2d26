"""Desires as utilities over goals: the candidate grids, what is read off weights over them,
and a person who ranks several goals (the paper's Scenarios 1 and 2, graded desires)."""

from __future__ import annotations

import numpy as np
import pytest

from brain.model.desires import (
    Desires,
    favourite_utilities,
    graded_utilities,
    most_wanted,
    preferred,
    ranking,
    ranking_text,
)
from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from sim2d.engine import Engine

SETTINGS = ModelSettings()


def test_favourites_are_the_papers_preferences() -> None:
    u = favourite_utilities(SETTINGS, 2)  # goals: item 0, item 1, out
    assert u.tolist() == [[30.0, 1.0, 2.0], [1.0, 30.0, 2.0], [1.0, 1.0, 30.0]], u.tolist()
    assert most_wanted(u).tolist() == np.eye(3).tolist(), "each favourite is its own most wanted goal"


def test_the_graded_grid() -> None:
    u = graded_utilities(ModelSettings(desire_levels=3), 2)
    assert u.shape == (3**3 - 1, 3), f"expected 26 vectors of 3 goals, got {u.shape}"
    assert set(u[:, 0]) == {1.0, 15.5, 30.0} and set(u[:, 2]) == {2.0, 16.0, 30.0}, (
        f"items take 1..30, out 2..30: {set(u[:, 0])}, {set(u[:, 2])}"
    )
    assert not np.any(np.all(u == [1.0, 1.0, 2.0], axis=1)), "all-low is not a desire"
    with pytest.raises(ValueError, match="desire_levels=1"):
        ModelSettings(desire_levels=1)
    with pytest.raises(ValueError, match="desire_model='many'"):
        ModelSettings(desire_model="many")


def test_ties_are_split_and_counted_half() -> None:
    u = np.array([[30.0, 30.0, 2.0]])
    assert most_wanted(u).tolist() == [[0.5, 0.5, 0.0]]
    assert preferred(u)[0].tolist() == [[0.5, 0.5, 1.0], [0.5, 0.5, 1.0], [0.0, 0.0, 0.5]]
    assert ranking_text(ranking(u[0]), ("skate", "ball", "out")) == "skate=ball>out"


def test_a_summary_of_weights() -> None:
    u = np.array([[30.0, 15.0, 2.0], [15.0, 30.0, 2.0]])
    summary = Desires(u).summarise(np.array([0.75, 0.25]))
    assert np.allclose(summary.utility, [26.25, 18.75, 2.0]), summary.utility
    assert summary.preferred[0, 1] == pytest.approx(0.75) and summary.preferred[1, 2] == pytest.approx(1.0)
    assert summary.ranking == ((0,), (1,), (2,)) and summary.probability(summary.ranking) == pytest.approx(
        0.75
    )


def _a1(scenario: str, desire_model: str, step: str) -> tuple[np.ndarray, np.ndarray]:
    """A1's smoothed (preference, P(goal a preferred to goal b)) at ``step``."""
    engine = Engine(scenario, robot="observe")
    tracker = MindTracker(engine.scene(), ModelSettings(desire_model=desire_model))
    tracker.observe(engine.state(), ())
    while not engine.done:
        result = engine.step()
        tracker.observe(result.state, result.events)
    tick = next(t for (t, who), label in tracker.labels.items() if who == "A1" and label == step)
    track = tracker.tracks["A1"]
    index = max(i for i, s in enumerate(track.steps) if s.tick <= tick)
    est = tracker.smoothed("A1")[index]
    assert est.desire is not None
    return est.preference, est.desire.preferred


def test_a_person_who_ranks_several_goals() -> None:
    """At step 6 A1 wants the skate most in Scenarios 1 and 2 alike. Later she leaves when it
    is taken (1) or plays with the ball instead (2): graded desires read that as "the ball
    second, above leaving" in 2 and not in 1, already at step 6; one favourite cannot say it."""
    skate, ball, out = 0, 1, 2
    graded = {s: _a1(s, "graded", "6") for s in ("paper-1", "paper-2")}
    for scenario, (preference, _) in graded.items():
        assert preference[skate] > 0.9, f"{scenario} step 6: P(skate most wanted) = {preference[skate]:.3f}"
    first, second = graded["paper-1"][1][ball, out], graded["paper-2"][1][ball, out]
    assert first < 0.2 and second > 0.6, (
        f"P(ball preferred to leaving) at step 6: Scenario 1 {first:.3f} (expected < 0.2), "
        f"Scenario 2 {second:.3f} (expected > 0.6)"
    )
    favourite = _a1("paper-2", "favourite", "6")[1][ball, out]
    assert favourite < 0.05, f"with one favourite, P(ball over leaving) in Scenario 2 = {favourite:.3f}"
