"""Reading the want where help matters (toyroom.evaluation.wantread), scored by hand."""

from __future__ import annotations

import pytest

from protocol import PREFERENCE_THRESHOLD, AgentMind, ItemBelief, ItemPlace, Mind, Prob, TrueMind, Truth
from toyroom.evaluation.metrics import Counts
from toyroom.evaluation.wantread import score_want, want_stretches


def truth(tick: int, ball_at: str, believed: str, wants: str = "ball") -> Truth:
    """Sally wants ``wants``; the ball is at ``ball_at``; she believes it at ``believed``."""
    return Truth(
        episode=1,
        tick=tick,
        agents=(
            TrueMind(
                agent="sally",
                beliefs=(ItemBelief(item="ball", locations=(Prob(believed, 1.0),)),),
                preference=wants,
            ),
        ),
        items=(ItemPlace(item="ball", location=ball_at), ItemPlace(item="doll", location="shelf")),
    )


def mind(tick: int, ball: float, doll: float, out: float) -> Mind:
    preference = (Prob("ball", ball), Prob("doll", doll), Prob("out", out))
    return Mind(episode=1, tick=tick, agents=(AgentMind(agent="sally", beliefs=(), preference=preference),))


TRUTHS = {
    1: truth(1, "box", "box"),  # she knows: no stretch
    2: truth(2, "basket", "box"),  # moved unseen: the stretch starts
    3: truth(3, "basket", "box"),
    4: truth(4, "basket", "basket"),  # she found out, has not taken it yet: still in the stretch
    5: truth(5, "sally", "sally"),  # took it at tick 5: the stretch ended
    6: truth(6, "basket", "box"),  # a second false belief later: a second stretch
    7: truth(7, "basket", "box", wants="doll"),  # her want changed (she believes rightly of the doll)
}
TAKES = [(5, "sally", "ball")]


def test_stretches_run_from_the_false_belief_to_the_take_of_the_wanted_item() -> None:
    wanting = want_stretches(TRUTHS, TAKES)
    inside = [tick for tick in sorted(wanting) if "sally" in wanting[tick]]
    assert inside == [2, 3, 4, 6], f"expected Sally's stretches at ticks 2-4 and 6, got {inside}"


def test_a_take_of_another_item_or_by_another_person_does_not_end_it() -> None:
    wanting = want_stretches(TRUTHS, [(3, "sally", "doll"), (3, "anne", "ball")])
    inside = [tick for tick in sorted(wanting) if "sally" in wanting[tick]]
    assert inside == [2, 3, 4, 5, 6], f"expected ticks 2-6 (no take of the ball by Sally), got {inside}"


def test_a_want_to_leave_has_no_stretch() -> None:
    truths = {1: truth(1, "basket", "box", wants="out")}
    assert want_stretches(truths, []) == {1: frozenset()}


def test_scores_by_hand() -> None:
    """P(ball) 0.7 at tick 2 (confident, top), 0.4 tied with the doll at tick 3 (top 1/2),
    0.1 at tick 4 (neither): mean P 0.4, confident 1/3, top (1 + 1/2 + 0) / 3."""
    minds = {2: mind(2, 0.7, 0.2, 0.1), 3: mind(3, 0.4, 0.4, 0.2), 4: mind(4, 0.1, 0.6, 0.3)}
    total = Counts()
    for tick, observed in minds.items():
        total.add_want(score_want(observed, TRUTHS[tick], frozenset({"sally"})))
    metrics = total.metrics()
    assert total.want_n == 3
    assert metrics["fb_want_p"] == pytest.approx(0.4)
    assert metrics["fb_want_confident"] == pytest.approx(1 / 3)
    assert metrics["fb_want_top"] == pytest.approx(0.5)


def test_the_threshold_is_inclusive_and_nobody_in_a_stretch_counts_nothing() -> None:
    at = score_want(
        mind(2, PREFERENCE_THRESHOLD, 0.3, 1 - PREFERENCE_THRESHOLD - 0.3), TRUTHS[2], frozenset({"sally"})
    )
    assert [s.confident for s in at] == [True], f"P = the threshold should count as confident, got {at}"
    assert score_want(mind(2, 0.7, 0.2, 0.1), TRUTHS[2], frozenset()) == []
    assert Counts().metrics()["fb_want_p"] is None


def test_counts_add_up_across_episodes() -> None:
    one, two = Counts(), Counts()
    one.add_want(score_want(mind(2, 1.0, 0.0, 0.0), TRUTHS[2], frozenset({"sally"})))
    two.add_want(score_want(mind(2, 0.0, 1.0, 0.0), TRUTHS[2], frozenset({"sally"})))
    one.add(two)
    assert (one.want_n, one.metrics()["fb_want_p"], one.metrics()["fb_want_confident"]) == (2, 0.5, 0.5)
