"""The errand mode beside the lasting desire (brain.model.modes): the chain's arithmetic, and
an errand explained as one on the tiny scene."""

from __future__ import annotations

import msgspec
import numpy as np
import pytest

from brain.model.desires import favourite_utilities, graded_utilities
from brain.model.modes import (
    CARRY,
    ERRAND,
    PURSUE,
    ModeColumns,
    ModeRates,
    ModeStep,
    carry_likelihood,
    errand_candidate,
    item_candidate,
    joint_likelihood,
    mode_step,
)
from brain.model.planner import drop_action, play_action
from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from tests.scenes import tiny_scene, tiny_state

RATES = ModeRates(errand_per_s=0.02, carry_per_s=0.03, resume_per_s=0.05, n_items=2)


def test_the_transition_compounds_exactly_and_keeps_the_long_run_shares() -> None:
    one, two = RATES.transition(3.0), RATES.transition(4.5)
    assert np.allclose(one @ two, RATES.transition(7.5), atol=1e-12), "T(s) T(t) should be T(s + t)"
    assert np.allclose(one.sum(axis=1), 1.0), f"rows should sum to 1, got {one.sum(axis=1)}"
    assert np.allclose(RATES.stationary @ RATES.generator, 0.0, atol=1e-15), (
        "the long-run shares are stationary"
    )
    assert np.array_equal(RATES.transition(0.0), np.eye(4)), "no time, no change"
    # pursue : errand : carry:0 : carry:1 = resume : errand : carry / K each
    assert np.allclose(RATES.stationary, np.array([0.05, 0.02, 0.015, 0.015]) / 0.1)
    # a long absence: whoever was on an errand has very likely turned back (to the long-run shares)
    assert RATES.transition(500.0)[ERRAND, PURSUE] == pytest.approx(RATES.stationary[PURSUE], abs=1e-6)


def test_each_mode_plans_as_the_candidate_it_names() -> None:
    settings = ModelSettings()
    assert errand_candidate(favourite_utilities(settings, 2)) == 2, "favourite: the row of out"
    assert item_candidate(favourite_utilities(settings, 2), 1) == 1, "favourite: the row of item 1"
    graded = graded_utilities(settings, 2)
    row = graded[errand_candidate(graded)]
    assert row[-1] == settings.leave_utility_out and (row[:-1] == settings.other_utility).all(), (
        f"graded: expected out high and every item low, got {row}"
    )


def test_each_mode_weighs_a_decision_by_its_own_likelihood() -> None:
    """Two items and out; one hypothesis, three desires. Not holding anything, a carry of item
    k is judged as wanting k; holding item 0, its carry takes any action but Play alike."""
    likelihood = np.array([[0.1, 0.3, 0.9]])  # the decision under ball, skate, out
    columns = ModeColumns(errand=2, items=(0, 1), epsilon=1e-3)
    free = joint_likelihood(likelihood, (5, 0, 0), columns)[0]  # (U, M)
    assert np.allclose(free[:, PURSUE], [0.1, 0.3, 0.9]) and np.allclose(free[:, ERRAND], 0.9)
    assert np.allclose(free[:, CARRY], 0.1) and np.allclose(free[:, CARRY + 1], 0.3)
    holding = joint_likelihood(likelihood, (5, 1, 0), columns)[0]
    assert np.allclose(holding[:, CARRY], carry_likelihood(0, 2, 1e-3)), "carrying the ball: any move alike"
    assert carry_likelihood(play_action(2), 2, 1e-3) < carry_likelihood(drop_action(2), 2, 1e-3) / 100


def test_a_drop_ends_the_carry_of_the_item_dropped() -> None:
    joint = np.zeros((1, 1, 4))
    joint[0, 0] = [0.2, 0.1, 0.6, 0.1]
    step = ModeStep(None, (5, 1, drop_action(2)), 0.0, np.eye(4))
    after, _ = mode_step(joint, step)
    assert np.allclose(after[0, 0], [0.8, 0.1, 0.0, 0.1]), f"the ball's carry should end, got {after[0, 0]}"


def walk_out_and_back(settings: ModelSettings) -> list[np.ndarray]:
    """On the tiny scene (the ball at A, the outside at the right end): the person walks
    towards the ball, turns, walks out, stays out 30 s and comes back in. P(ball) online."""
    tracker = MindTracker(tiny_scene(), settings)
    path = [(3, 0), (2, 0), (1, 0), (2, 0), (3, 0), (4, 0), (4, 0), (4, 0), (3, 0), (2, 0)]
    time = 0.0
    for tick, cell in enumerate(path):
        tracker.observe(msgspec.structs.replace(tiny_state(tick, cell, "A"), time=round(time, 9)), ())
        time += 15.0 if tick in (5, 6) else 0.7
    return [e.preference for e in tracker.tracks["p"].estimates]


def test_an_errand_keeps_the_lasting_desire() -> None:
    """Without errands, walking out reads as wanting to leave (P(ball) near 0 while out);
    with them, the want shown before the walk survives it, and coming back resumes it."""
    with_modes, without = (
        walk_out_and_back(ModelSettings(errand_per_s=0.02)),
        walk_out_and_back(ModelSettings(errand_per_s=0.0, carry_per_s=0.0)),
    )
    outside = 5  # the step onto the outside cell
    assert without[outside][0] < 0.05, (
        f"expected no errands to read leaving, got P(ball) {without[outside][0]:.3f}"
    )
    assert with_modes[outside][0] > 0.3, (
        f"expected the errand to keep P(ball), got {with_modes[outside][0]:.3f}"
    )
    assert with_modes[-2][0] > 0.95, f"expected coming back to resume the ball, got {with_modes[-2][0]:.3f}"


def test_a_carry_dilutes_the_want_read_from_a_walk_to_the_item() -> None:
    """The carry's price, measured in docs/model.md: a walk to the ball is also a walk to put it
    away, so P(ball) from the same walk is lower with carries than without."""
    carry, errand = (walk_out_and_back(ModelSettings(errand_per_s=0.02, carry_per_s=c)) for c in (0.02, 0.0))
    assert carry[2][0] < errand[2][0] - 0.1, (
        f"expected carries to dilute P(ball): {carry[2][0]:.3f} against {errand[2][0]:.3f}"
    )
