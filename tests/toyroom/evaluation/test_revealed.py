"""The metrics of false beliefs read from behaviour, on a hand-built episode whose scores are
computed by hand: ``revealed_detection`` and its lead (item by item and item-agnostic),
``knowable_false_belief_f1``, and the
Brier score, log loss and Brier skill of P(false belief)."""

from __future__ import annotations

import math

import pytest

from protocol import ItemBelief, ItemPlace, Prob, Pursuit, TrueMind, Truth
from toyroom.evaluation.metrics import EPS, Counts, EpisodeOutcome, majority_counts
from toyroom.evaluation.revealed import Stretch, heading_wrong, knowable, stretches
from toyroom.evaluation.runs import TruthView, _score
from toyroom.evaluation.scoredminds import Chance, ScoredAgent, ScoredBelief, ScoredMind

SPOTS = {"L1": (0, 0), "L2": (7, 0)}
BALL_P = [0.1, 0.2, 0.3, 0.6, 0.7, 0.8, 0.1]
"""The observer's P(false belief about the ball) at ticks 0..6 (flagged above 0.5: 3, 4, 5)."""


def truth(tick: int) -> Truth:
    """A1 wants the ball, which rests at L1 throughout. Ticks 0-1: A1 does not know where it
    is (half each: ignorance, no false belief); 2-5: sure it is at L2 and heading there (a
    revealed false belief; A1 stands next to L2 from tick 5); 6: sure of L1 (put right). The
    skate rests at L2, and A1 is sure it is at L1 and never goes for it: a false belief that
    nothing shows."""
    ball = {0: 0.5, 1: 0.5}.get(tick, 0.0 if tick < 6 else 1.0)
    pursuit = Pursuit("ball", "L2") if 2 <= tick <= 5 else Pursuit("ball", "L1") if tick == 6 else None
    mind = TrueMind(
        agent="A1",
        beliefs=(
            ItemBelief("ball", (Prob("L1", ball), Prob("L2", 1.0 - ball))),
            ItemBelief("skate", (Prob("L1", 1.0), Prob("L2", 0.0))),
        ),
        preference="ball",
        pursuit=pursuit,
    )
    return Truth(
        episode=1, tick=tick, agents=(mind,), items=(ItemPlace("ball", "L1"), ItemPlace("skate", "L2"))
    )


def mind(tick: int) -> ScoredMind:
    chances = (Chance("ball", BALL_P[tick]), Chance("skate", 0.0))
    agent = ScoredAgent(
        agent="A1",
        beliefs=(ScoredBelief("ball", (Chance("L1", 1.0),)), ScoredBelief("skate", (Chance("L1", 1.0),))),
        preference=(Chance("ball", 1.0),),
        false_beliefs=("ball",) if BALL_P[tick] > 0.5 else (),
        false_belief=chances,
    )
    return ScoredMind(tick=tick, agents=(agent,))


TRUTHS = {t: truth(t) for t in range(7)}
CELLS = {t: {"A1": (t, 0)} for t in range(7)}
"""A1 walks one cell a tick from (0, 0): next to L2 (7, 0) only from tick 6, after the stretch."""


def test_a_revealed_stretch_runs_while_the_pursuit_shows_the_belief() -> None:
    found = stretches(TRUTHS, CELLS, SPOTS)
    assert found == [Stretch("A1", "ball", "L2", first=2, last=5, deadline=6)], found


def test_a_stretch_without_two_steps_shows_nothing() -> None:
    standing = {t: {"A1": (min(t, 3), 0)} for t in range(7)}  # stops at (3, 0) from tick 3
    assert stretches(TRUTHS, standing, SPOTS) == [], "two cells walked (2, 3) are one step"


def test_only_revealed_or_moved_false_beliefs_are_knowable() -> None:
    view = TruthView(TRUTHS, {}, stretches(TRUTHS, CELLS, SPOTS))
    assert view.causes[2] == {("A1", "ball"): "unmoved", ("A1", "skate"): "start"}
    known = knowable(TRUTHS, view.causes, view.stretches)
    assert [sorted(known[t]) for t in range(7)] == [[], [], *[[("A1", "ball")]] * 4, []]


def test_the_scores_are_the_hand_computed_ones() -> None:
    view = TruthView(TRUTHS, {}, stretches(TRUTHS, CELLS, SPOTS))
    counts = _score({t: mind(t) for t in range(7)}, view, EpisodeOutcome()).counts
    scores = counts.metrics()
    # Detected at tick 3, before the stretch ends (tick 6): one stretch of one, lead 3 ticks.
    assert (scores["revealed_detection"], scores["revealed_lead_median"]) == (1.0, 3.0)
    # Knowable: the ball at ticks 2-5 (flagged at 3, 4, 5); the skate's false belief counts
    # neither way; ticks 0, 1, 6 are negatives (none flagged). Precision 1, recall 3/4.
    assert (counts.known_tp, counts.known_fn, counts.known_fp, counts.known_tn) == (3, 1, 0, 3)
    assert scores["knowable_false_belief_f1"] == pytest.approx(2 * 0.75 / 1.75)
    # Every person-item-tick: the ball's 7 (squared errors 0.84 in all) and the skate's 7
    # (P 0 against a false belief: 1 each).
    assert scores["brier"] == pytest.approx((0.84 + 7) / 14)
    rate = 11 / 14
    assert scores["brier_skill"] == pytest.approx(1 - (7.84 / 14) / (rate * (1 - rate)))
    ball = -sum(math.log(q) for q in (0.9, 0.8, 0.3, 0.6, 0.7, 0.8, 0.9))
    assert scores["log_loss"] == pytest.approx((ball - 7 * math.log(EPS)) / 14)


def test_flagging_too_late_or_never_is_no_detection() -> None:
    view = TruthView(TRUTHS, {}, stretches(TRUTHS, CELLS, SPOTS))
    late = {t: mind(t) for t in range(7)}
    late[3] = late[4] = late[5] = mind(2)  # flagged only at tick 6: the stretch is over
    scores = _score(late, view, EpisodeOutcome()).counts.metrics()
    assert scores["revealed_detection"] == 0.0 and scores["revealed_lead_median"] is None


def test_a_majority_observer_never_flags_and_scores_the_base_rate_worse() -> None:
    view = TruthView(TRUTHS, {}, stretches(TRUTHS, CELLS, SPOTS))
    counts = _score({t: mind(t) for t in range(7)}, view, EpisodeOutcome()).counts
    majority = majority_counts(counts, "ball").metrics()
    assert majority["revealed_detection"] == 0.0 and majority["knowable_false_belief_f1"] == 0.0
    assert majority["brier"] == pytest.approx(11 / 14)
    total = Counts()
    total.add(counts)
    total.add(counts)
    assert total.metrics()["brier"] == pytest.approx(counts.metrics()["brier"]) and total.leads == [3, 3]


def reading(tick: int, wants: dict[str, float], ball_at_l2: float) -> ScoredMind:
    """An observer that never flags an item (no false belief named) but reads A1 as wanting
    ``wants`` and believing the ball at L2 with ``ball_at_l2`` from tick 4 (at L1 before) and
    the skate at L2 (where it rests: no mistake)."""
    ball = ball_at_l2 if tick >= 4 else 0.0
    agent = ScoredAgent(
        agent="A1",
        beliefs=(
            ScoredBelief("ball", (Chance("L1", 1.0 - ball), Chance("L2", ball))),
            ScoredBelief("skate", (Chance("L2", 1.0),)),
        ),
        preference=tuple(Chance(item, p) for item, p in wants.items()),
    )
    return ScoredMind(tick=tick, agents=(agent,))


def test_an_item_agnostic_reading_detects_a_walk_to_the_wrong_place() -> None:
    view = TruthView(TRUTHS, {}, stretches(TRUTHS, CELLS, SPOTS))
    # wants the ball 0.6, believes it at L2 0.9 from tick 4: 0.54 > 0.5, lead 6 - 4 = 2 ticks,
    # though the observer never names the ball's false belief
    read = {t: reading(t, {"ball": 0.6, "skate": 0.4}, 0.9) for t in range(7)}
    scores = _score(read, view, EpisodeOutcome()).counts.metrics()
    assert (scores["revealed_detection_any"], scores["revealed_lead_any_median"]) == (1.0, 2.0), scores
    assert scores["revealed_detection"] == 0.0, "no item was flagged: the item-specific metric misses it"
    # the skate rests at L2: wanting it more (0.6) is no mistake, and the ball's 0.4 x 0.9 = 0.36
    skate = {t: reading(t, {"ball": 0.4, "skate": 0.6}, 0.9) for t in range(7)}
    assert _score(skate, view, EpisodeOutcome()).counts.metrics()["revealed_detection_any"] == 0.0
    # the item-specific flag of the first fixture also reads as heading wrong? Its beliefs put
    # the ball at L1, so no: the two metrics measure different readings
    flagged = _score({t: mind(t) for t in range(7)}, view, EpisodeOutcome()).counts.metrics()
    assert flagged["revealed_detection_any"] == 0.0 and flagged["revealed_detection"] == 1.0


def test_heading_wrong_sums_over_the_items_not_resting_there() -> None:
    agent = reading(5, {"ball": 0.3, "skate": 0.3, "kite": 0.3}, 1.0).agents[0]
    kite = ScoredBelief("kite", (Chance("L2", 1.0),))
    agent = ScoredAgent("A1", (*agent.beliefs, kite), agent.preference)
    where = {"ball": "L1", "skate": "L2", "kite": "L1"}
    assert heading_wrong(agent, "L2", where) == pytest.approx(0.6), "ball 0.3 + kite 0.3; the skate is there"
    assert heading_wrong(agent, "L1", where) == 0.0
    carried = {**where, "kite": None}  # someone carries the kite: it counts neither way
    assert heading_wrong(agent, "L2", carried) == pytest.approx(0.3), "the ball alone"
