"""Waiting is a decision: a person who stands still while a decision is due has chosen the
planner's Stay, and its likelihood is evidence (the tiny corridor of ``tests/scenes.py``:
the person comes in from the outside and pauses on B)."""

from __future__ import annotations

import msgspec
import numpy as np
import pytest

from brain.model.planner import Move
from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from protocol import Activity, Observer
from tests.scenes import tiny_scene, tiny_state

IN_AND_PAUSE = [(4, 0), (3, 0), (2, 0)] + [(2, 0)] * 6 + [(3, 0)]
"""Ticks 0-9 (0.7 s each): in from the outside to B, six ticks (4.2 s) still, then back."""


def run(path: list[tuple[int, int]], **settings: float | str) -> MindTracker:
    tracker = MindTracker(tiny_scene(), ModelSettings(**settings), Observer.BTOM)  # type: ignore[arg-type]
    for tick, cell in enumerate(path):
        tracker.observe(tiny_state(tick, cell, "A"), ())
    return tracker


def decisions(tracker: MindTracker) -> list[tuple[int, int | None]]:
    return [(s.tick, s.decision[2] if s.decision else None) for s in tracker.tracks["p"].steps]


@pytest.mark.parametrize("belief_model", ["point", "graded"])
def test_a_long_pause_is_one_stay_decision(belief_model: str) -> None:
    steps = decisions(run(IN_AND_PAUSE, belief_model=belief_model))
    stays = [tick for tick, action in steps if action == Move.STAY]
    # the pause starts at tick 2 and reaches 3 x 0.7 s at tick 5; the rest of it adds nothing
    assert stays == [5], f"expected one Stay at tick 5, got Stays at {stays} (steps {steps})"
    ignored = decisions(run(IN_AND_PAUSE, belief_model=belief_model, wait_decisions=0.0))
    assert all(action != Move.STAY for _, action in ignored), f"wait_decisions = 0 counted a wait: {ignored}"
    short = decisions(run(IN_AND_PAUSE[:3] + [(2, 0)] * 2 + [(3, 0)], belief_model=belief_model))
    assert all(action != Move.STAY for _, action in short), f"a 1.4 s pause counted as a wait: {short}"


@pytest.mark.parametrize("belief_model", ["point", "graded"])
def test_a_long_wait_before_turning_back_counts_as_evidence(belief_model: str) -> None:
    """Without preference switches (hazard 0), the posterior odds of ``out`` against the ball
    after the pause are the odds without it times the likelihood ratio of Stay on B."""
    waited = run(IN_AND_PAUSE, belief_model=belief_model, hazard=0.0)
    ignored = run(IN_AND_PAUSE, belief_model=belief_model, hazard=0.0, wait_decisions=0.0)
    odds = [t.online("p").preference[1] / t.online("p").preference[0] for t in (waited, ignored)]
    model = waited.model
    policy = waited.person_model.policy
    truth = model.world_index(np.array(waited.truth))
    stay = policy.action_likelihood(model.cell_index[(2, 0)], 0, Move.STAY)[truth]  # (D,) ball, out
    expected = stay[1] / stay[0]
    assert abs(expected - 1.0) > 0.2, f"Stay on B should tell ball from out apart; ratio {expected:.3f}"
    assert odds[0] / odds[1] == pytest.approx(expected, rel=0.02), (
        f"expected the wait to multiply the odds of out by {expected:.3f}, got {odds[0] / odds[1]:.3f}"
    )


def test_standing_outside_or_playing_is_not_a_wait() -> None:
    outside = decisions(run([(4, 0)] * 8))
    assert all(action != Move.STAY for _, action in outside), f"standing outside counted: {outside}"
    tracker = MindTracker(tiny_scene(), ModelSettings(), Observer.BTOM)
    for tick, cell in enumerate([(4, 0), (3, 0), (2, 0), (1, 0), (0, 0)]):
        tracker.observe(tiny_state(tick, cell, "A"), ())
    for tick in range(5, 12):  # holding the ball on A and playing with it
        state = tiny_state(tick, (0, 0), None, holding=True)
        person = msgspec.structs.replace(state.agents[0], activity=Activity.PLAYING)
        tracker.observe(msgspec.structs.replace(state, agents=(person,)), ())
    playing = decisions(tracker)
    assert all(action != Move.STAY for _, action in playing), f"playing counted as waiting: {playing}"
