"""Belief-space planning: the planner's beliefs stay on their points, certain beliefs give
the point planner's values, QMDP is never below it, and going to look has value."""

from __future__ import annotations

import numpy as np
import pytest

from brain.model.graded import qmdp_likelihood
from brain.model.lookahead import belief_points, look_transitions, solve
from brain.model.planner import Move, plan
from brain.model.world import build_world_model
from brain.settings import ModelSettings
from sim2d.engine import Engine
from tests.scenes import lookout_scene

SETTINGS = ModelSettings()


@pytest.fixture(scope="module")
def paper():
    model = build_world_model(Engine("paper-1").scene())
    return model, solve(model, SETTINGS), plan(model, SETTINGS)


def test_looking_keeps_beliefs_on_their_points(paper) -> None:
    model, *_ = paper
    points = belief_points(model.sees, 2)
    assert len(points) == 11, f"expected the 10 grid points and 'unavailable', got {len(points)}"
    look = look_transitions(points, model.sees)
    assert np.allclose(look.sum(axis=2), 1.0), "every row of a look transition is a distribution"


def test_certain_beliefs_give_the_point_planners_values(paper) -> None:
    model, lookahead, policy = paper
    K, W = model.n_items, model.n_worlds
    worst = 0.0
    for skate in range(model.n_locations):
        for ball in range(model.n_locations):
            j = (
                lookahead.certain[skate] * lookahead.strides[0]
                + lookahead.certain[ball] * lookahead.strides[1]
            )
            w = int(model.world_index(np.array([2 * skate, 2 * ball])))
            for c in range(model.n_cells):
                point = policy.q[:, (c * (K + 1)) * W + w].max(axis=1)
                worst = max(worst, float(np.abs(point - lookahead.value[:, c, 0, j]).max()))
    assert worst < 1e-9, f"belief-space values of certain beliefs differ from the point planner's by {worst}"


def test_qmdp_is_never_below_belief_space_values(paper) -> None:
    """QMDP assumes the uncertainty resolves after one step: an upper bound."""
    model, lookahead, policy = paper
    K, W = model.n_items, model.n_worlds
    rng = np.random.default_rng(0)
    for _ in range(50):
        c = int(rng.integers(model.n_cells))
        j = int(rng.integers(len(lookahead.points) - 1, size=1)[0]) * lookahead.strides[0] + int(
            rng.integers(len(lookahead.points) - 1)
        )
        digits = [(j // s) % (len(lookahead.points) + 1) for s in lookahead.strides]
        b = np.ones(W)
        for k, d in enumerate(digits):
            per_value = np.zeros(model.n_values)
            per_value[0::2] = lookahead.points[d][: model.n_locations]
            b *= per_value[model.worlds[:, k]]
        if b.sum() == 0:
            continue
        q = policy.q[:, (c * (K + 1)) * W : (c * (K + 1) + 1) * W]  # (U, W, A)
        qmdp = np.einsum("w,uwa->ua", b, np.where(np.isfinite(q), q, -1e9)).max(axis=1)
        assert np.all(qmdp >= lookahead.value[:, c, 0, j] - 1e-9), f"cell {c}, beliefs {digits}"


def test_going_to_look_has_value() -> None:
    """In the middle of the lookout corridor, unsure whether the ball is at A or at B, a
    ball lover who plans over what they will see steps up to the lookout; by QMDP they walk
    to one end."""
    model = build_world_model(lookout_scene())
    lookahead = solve(model, SETTINGS)
    policy = plan(model, SETTINGS)
    middle = model.cell_index[(3, 0)]
    belief = np.array([[0.5, 0.0, 0.5, 0.0]])  # the ball resting at A or at B
    ball = 0  # the favourite-ball desire
    moves = {name: move for name, move in (("up", Move.UP), ("left", Move.LEFT), ("right", Move.RIGHT))}
    rest = belief[:, None, 0::2]  # (1, K, L)
    looking = {
        n: float(lookahead.likelihood(rest, middle, 0, m, 2.0, 0.0)[0, ball]) for n, m in moves.items()
    }
    q = policy.q[:, policy.state_slice(middle, 0), :]
    qmdp = {n: float(qmdp_likelihood(belief, q, m, 2.0, 0.0)[0, ball]) for n, m in moves.items()}
    assert looking["up"] > max(looking["left"], looking["right"]), f"belief-space planning: {looking}"
    assert qmdp["up"] < min(qmdp["left"], qmdp["right"]), f"QMDP: {qmdp}"


def test_the_tracker_with_belief_space_planning_passes_sally_anne() -> None:
    """End to end on the engine's stream: Sally, who did not see the move, has a false
    belief; Anne, who made it, has none."""
    from brain.tracking.tracker import MindTracker

    engine = Engine("sally-anne")
    tracker = MindTracker(engine.scene(), ModelSettings(person_planner="belief"))
    assert tracker.person_model.lookahead is not None  # type: ignore[attr-defined]
    tracker.observe(engine.state(), ())
    after = None
    while not engine.done and after is None:
        result = engine.step()
        tracker.observe(result.state, result.events)
        if any(e.kind.value == "drop" and e.actor == "anne" for e in result.events):
            after = (tracker.online("sally"), tracker.online("anne"))
    assert after is not None and after[0] is not None and after[1] is not None, "Anne never moved the marble"
    marble = tracker.model.items.index("marble")
    assert after[0].false_belief[marble] > 0.8, (
        f"Sally: P(false belief) = {after[0].false_belief[marble]:.3f}"
    )
    assert after[1].false_belief[marble] < 0.2, f"Anne: P(false belief) = {after[1].false_belief[marble]:.3f}"
