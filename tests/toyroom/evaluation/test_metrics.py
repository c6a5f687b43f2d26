"""The evaluation metrics on a tiny episode computed by hand."""

from __future__ import annotations

import msgspec
import pytest

from protocol import AgentMind, ItemBelief, ItemPlace, Mind, Prob, TrueMind, Truth
from toyroom.evaluation.metrics import SUMS, Counts, false_belief_causes, score_tick
from toyroom.evaluation.summary import CauseRecall


def mind(tick: int, basket: float, flagged: bool, prefers: str) -> Mind:
    return Mind(
        episode=1,
        tick=tick,
        agents=(
            AgentMind(
                agent="sally",
                beliefs=(
                    ItemBelief(item="marble", locations=(Prob("basket", basket), Prob("box", 1 - basket))),
                ),
                preference=(
                    Prob("marble", 0.7 if prefers == "marble" else 0.2),
                    Prob("out", 0.3 if prefers == "marble" else 0.8),
                ),
                false_beliefs=("marble",) if flagged else (),
            ),
        ),
    )


def truth(tick: int, basket: float, prefers: str) -> Truth:
    return Truth(
        episode=1,
        tick=tick,
        agents=(
            TrueMind(
                agent="sally",
                beliefs=(
                    ItemBelief(item="marble", locations=(Prob("basket", basket), Prob("box", 1 - basket))),
                ),
                preference=prefers,
            ),
        ),
    )


def test_a_three_tick_episode_by_hand() -> None:
    """Tick 1: the marble is in the basket, Sally believes so; the brain says 0.9 basket.
    Tick 2: Anne moved it to the box unseen: Sally's belief is false; the brain flags it.
    Tick 3: Sally still believes the basket; the brain, wrongly, thinks she knows (no flag)
    and has taken... nothing yet; preference counts only once she took something (tick 3)."""
    total = Counts()
    total.add(score_tick(mind(1, 0.9, False, "marble"), truth(1, 1.0, "marble"), {"marble": "basket"}, set()))
    total.add(score_tick(mind(2, 0.8, True, "marble"), truth(2, 1.0, "marble"), {"marble": "box"}, set()))
    total.add(score_tick(mind(3, 0.3, False, "out"), truth(3, 1.0, "marble"), {"marble": "box"}, {"sally"}))
    # TV: |1-0.9| -> 0.1, then 0.2, then 0.7; mean 1/3
    assert total.tv_n == 3 and total.tv_sum == pytest.approx(1.0)
    # flags: tick 1 true negative, tick 2 true positive, tick 3 false negative
    assert (total.tp, total.fp, total.fn, total.tn) == (1, 0, 1, 1)
    m = total.metrics()
    assert m["belief_tv"] == pytest.approx(1 / 3)
    assert m["false_belief_precision"] == 1.0 and m["false_belief_recall"] == 0.5
    assert m["false_belief_f1"] == pytest.approx(2 / 3)
    # preference: counted at tick 3 only, and wrong there
    assert (total.pref_hits, total.pref_n) == (0, 1) and m["preference_accuracy"] == 0.0


def test_goal_false_beliefs_count_only_the_wanted_item() -> None:
    """The same three ticks, but Sally wants to leave at tick 3: her false belief about the
    marble then counts for the overall F1 and not for the goal F1."""
    total = Counts()
    total.add(score_tick(mind(1, 0.9, False, "marble"), truth(1, 1.0, "marble"), {"marble": "basket"}, set()))
    total.add(score_tick(mind(2, 0.8, True, "marble"), truth(2, 1.0, "marble"), {"marble": "box"}, set()))
    total.add(score_tick(mind(3, 0.3, False, "out"), truth(3, 1.0, "out"), {"marble": "box"}, {"sally"}))
    assert (total.goal_tp, total.goal_fp, total.goal_fn, total.goal_tn) == (1, 0, 0, 1), total
    assert (total.tp, total.fn) == (1, 1)
    m = total.metrics()
    assert m["goal_false_belief_f1"] == 1.0 and m["false_belief_f1"] == pytest.approx(2 / 3), m
    majority = total.majority().metrics()
    assert majority["goal_false_belief_f1"] == 0.0, "the majority observer never flags: it misses tick 2"


def test_no_flags_at_all_has_no_precision() -> None:
    counts = score_tick(mind(1, 1.0, False, "marble"), truth(1, 1.0, "marble"), {"marble": "box"}, set())
    m = counts.metrics()
    assert m["false_belief_precision"] is None and m["false_belief_recall"] == 0.0
    assert m["false_belief_f1"] == 0.0, "a false belief happened and was missed: F1 is 0, not undefined"


def test_ignorance_is_not_a_false_belief() -> None:
    """Sally unsure between basket and box (half each) with the marble in the box: ignorance,
    not a false belief; with less than 0.1 on the box, a false belief."""
    unsure = score_tick(mind(1, 0.5, False, "marble"), truth(1, 0.5, "marble"), {"marble": "box"}, set())
    assert (unsure.tp, unsure.fp, unsure.fn, unsure.tn) == (0, 0, 0, 1)
    sure = score_tick(mind(1, 0.95, True, "marble"), truth(1, 0.95, "marble"), {"marble": "box"}, set())
    assert (sure.tp, sure.fp, sure.fn, sure.tn) == (1, 0, 0, 0)


def test_the_majority_class_observer() -> None:
    """Always the most common true preference, never a false belief."""
    total = Counts()
    for tick, prefers in enumerate(("marble", "marble", "out"), start=1):
        total.add(
            score_tick(mind(tick, 0.8, True, "out"), truth(tick, 1.0, prefers), {"marble": "box"}, {"sally"})
        )
    majority = total.majority().metrics()
    assert majority["preference_accuracy"] == pytest.approx(2 / 3)
    assert majority["false_belief_recall"] == 0.0 and majority["false_belief_f1"] == 0.0
    assert majority["belief_tv"] is None


def test_paired_bootstrap_intervals() -> None:
    from toyroom.evaluation.intervals import intervals

    good = [Counts(tp=9, fn=1, tn=10, tv_sum=1.0, tv_n=10) for _ in range(20)]
    bad = [Counts(tp=2, fp=3, fn=8, tn=7, tv_sum=4.0, tv_n=10) for _ in range(20)]
    bounds, differences = intervals({"btom": good, "other": bad}, seed=1, resamples=200)
    f1 = bounds["btom"]["false_belief_f1"]
    assert f1["lo"] <= f1["mean"] <= f1["hi"] and f1["mean"] == pytest.approx(2 * 0.9 * 1.0 / 1.9)
    diff = differences["other"]["false_belief_f1"]
    assert diff["lo"] > 0, f"btom should beat the other observer on every resample: {diff}"
    assert differences["other"]["belief_tv"]["hi"] < 0, "btom's belief_tv is lower"
    again, _ = intervals({"btom": good, "other": bad}, seed=1, resamples=200)
    assert again == bounds, "the same seed should give the same intervals"


def placed(tick: int, basket: float, where: str) -> Truth:
    """:func:`truth` (Sally wants the marble) with the marble truly at ``where``."""
    return msgspec.structs.replace(truth(tick, basket, "marble"), items=(ItemPlace("marble", where),))


def test_false_beliefs_by_how_they_arose() -> None:
    """Tick 1: Sally sure of the box, the marble in the basket (from before the episode:
    ``start``). Tick 2: she saw it (true belief). Tick 3: Anne moved it to the box unseen
    (``moved``). Tick 4: still. Tick 5: she looked, knows the box. Tick 6: told wrongly it is
    in the basket, nothing moved (``unmoved``). The brain flags ticks 3 and 6 only."""
    truths = {
        1: placed(1, 0.0, "basket"),
        2: placed(2, 1.0, "basket"),
        3: placed(3, 1.0, "box"),
        4: placed(4, 1.0, "box"),
        5: placed(5, 0.0, "box"),
        6: placed(6, 1.0, "box"),
    }
    causes = false_belief_causes(truths)
    key = ("sally", "marble")
    assert {t: c.get(key) for t, c in causes.items()} == {
        1: "start",
        2: None,
        3: "moved",
        4: "moved",
        5: None,
        6: "unmoved",
    }
    total = Counts()
    for tick, t in truths.items():
        where = {p.item: p.location for p in t.items}
        flagged = tick in (3, 6)
        total.add(score_tick(mind(tick, 0.5, flagged, "marble"), t, where, set(), causes[tick]))
    by_cause = total.recall_by_cause()
    assert by_cause["start"] == CauseRecall(ticks=1, share=0.25, recall=0.0), by_cause
    assert by_cause["moved"] == CauseRecall(ticks=2, share=0.5, recall=0.5), by_cause
    assert by_cause["unmoved"] == CauseRecall(ticks=1, share=0.25, recall=1.0), by_cause
    assert total.majority().recall_by_cause()["moved"].recall == 0.0


def test_sums_are_the_number_fields_of_counts_as_the_hand_list_had_them() -> None:
    """``SUMS``, derived from :class:`Counts`' fields, is the tuple once written out by hand
    (with ``detected_any``, issue 53, since)."""
    assert SUMS == (
        "tv_sum",
        "tv_n",
        "pref_hits",
        "pref_n",
        "tp",
        "fp",
        "fn",
        "tn",
        "goal_tp",
        "goal_fp",
        "goal_fn",
        "goal_tn",
        "known_tp",
        "known_fp",
        "known_fn",
        "known_tn",
        "brier_sum",
        "log_loss_sum",
        "prob_n",
        "fb_n",
        "stretches",
        "detected",
        "detected_any",
        "nested_n",
        "nested_right",
        "nested_first_right",
        "want_p_sum",
        "want_confident",
        "want_top_sum",
        "want_n",
    )
