"""One false-belief rule (``protocol.is_false_belief``) for the brain and for the evaluation
that scores it: a belief is false when it gives the item's true place less than
``FALSE_BELIEF_MASS`` times its likeliest place's. Until issue 50 the scorer used a fixed
``< 0.1``, which called ignorance over more than ten places (each under 0.1) a false belief
where the brain, reading against the likeliest place, called it ignorance."""

from __future__ import annotations

import numpy as np

from brain.model.estimates import Estimate, false_belief_probability
from protocol import (
    FALSE_BELIEF_MASS,
    AgentMind,
    ItemBelief,
    Mind,
    Prob,
    TrueMind,
    Truth,
    believes_falsely,
    is_false_belief,
)
from toyroom.evaluation.metrics import score_tick

PLACES = tuple(f"S{i}" for i in range(16))
SPREAD = np.r_[np.full(12, 1 / 12), np.zeros(4)]
"""Ignorance over 12 of 16 places, the truth (S5) among them: 1/12 on each, under 0.1."""
LOPSIDED = np.r_[0.9, 0.045, np.full(14, 0.055 / 14)]
"""Sure of S0, a twentieth of that on the truth (S1): a false belief."""
TRUE_PLACE = {"ball": "S5", "skate": "S1"}


def _as_map(belief: np.ndarray) -> dict[str, float]:
    return {place: float(p) for place, p in zip(PLACES, belief, strict=True) if p > 0}


def test_the_rule_reads_against_the_likeliest_place() -> None:
    assert not is_false_belief(1 / 12, 1 / 12), "an even spread over 12 places is ignorance"
    assert 1 / 12 < FALSE_BELIEF_MASS, "the old fixed rule called that spread a false belief"
    assert is_false_belief(0.045, 0.9), "a twentieth of the likeliest place's share is a false belief"
    assert not believes_falsely({"S0": 0.6, "S1": 0.07, "S2": 0.33}, "S1"), (
        "0.07 is more than 0.1 x 0.6: not false, though under the old fixed 0.1"
    )
    assert believes_falsely({"S0": 1.0}, "S1") and not believes_falsely({}, "S1")
    flags = is_false_belief(np.array([1 / 12, 0.045]), np.array([1 / 12, 0.9]))
    assert flags.tolist() == [False, True], f"element-wise on arrays: expected [False, True], got {flags}"


def test_the_brain_and_the_scorer_agree_on_ignorance_over_twelve_places() -> None:
    """The brain's P(false belief) for a person certain of these beliefs is 0 for the spread
    ball and 1 for the lopsided skate; the scorer, given the same beliefs as the truth and
    the brain's flags, counts a true negative and a true positive (the old fixed rule scored
    the ball a missed false belief: a false negative)."""
    beliefs = np.stack([SPREAD, LOPSIDED])[None]  # (G = 1, K = 2: ball, skate; L = 16)
    est = Estimate(beliefs[0], np.ones(3) / 3, (None, None, 1.0), np.zeros(2), (np.ones(1), beliefs))
    truth_values = tuple(2 * PLACES.index(TRUE_PLACE[item]) for item in ("ball", "skate"))
    p = false_belief_probability(est, truth_values, FALSE_BELIEF_MASS)
    assert p.tolist() == [0.0, 1.0], f"the brain: expected P(false belief) [0, 1], got {p}"
    items = ("ball", "skate")
    item_beliefs = tuple(
        ItemBelief(item, tuple(Prob(place, q) for place, q in _as_map(b).items()))
        for item, b in zip(items, (SPREAD, LOPSIDED), strict=True)
    )
    truth = Truth(episode=1, tick=1, agents=(TrueMind("sally", item_beliefs, preference="ball"),))
    mind = Mind(
        episode=1,
        tick=1,
        agents=(
            AgentMind(
                "sally",
                item_beliefs,
                preference=(Prob("ball", 1.0),),
                false_beliefs=tuple(item for item, q in zip(items, p, strict=True) if q > 0.5),
                false_belief=tuple(Prob(item, float(q)) for item, q in zip(items, p, strict=True)),
            ),
        ),
    )
    counts = score_tick(mind, truth, dict(TRUE_PLACE), set())
    cells = (counts.tp, counts.fp, counts.fn, counts.tn)
    assert cells == (1, 0, 0, 1), f"the scorer: expected (tp, fp, fn, tn) = (1, 0, 0, 1), got {cells}"
    assert (counts.goal_fn, counts.goal_tn) == (0, 1), "the ball, wanted, is ignorance: a true negative"
