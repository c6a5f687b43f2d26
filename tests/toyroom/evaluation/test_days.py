"""A households evaluation's numbers by day (:mod:`toyroom.evaluation.days`): days pooled with
each household one cluster, its people told apart by day."""

from __future__ import annotations

from toyroom.evaluation.conditions import Condition
from toyroom.evaluation.days import LATER, by_day, merged, table
from toyroom.evaluation.helpfulness import PersonHelp
from toyroom.evaluation.metrics import Counts
from toyroom.evaluation.records import EpisodeRecord, RunScores


def _day(index: int, day: int, goal: int | None, tp: int) -> EpisodeRecord:
    def run(goal_tick: int | None) -> RunScores:
        return RunScores(
            counts=Counts(tp=tp, stretches=2, detected=tp, pref_truth={"ball": 1}),
            outcome={"A1": goal_tick is not None},
            ticks_to_goal={"A1": goal_tick},
            episode_ticks=300,
            ticks=301,
            help={"A1": PersonHelp(false_belief=True, false_belief_tick=10, goal_tick=goal_tick)},
        )

    observers = {name: run(goal) for name in ("btom", "truebelief", "perceptonly", "motion", "btom-fresh")}
    return EpisodeRecord(
        index=index,
        map="paper",
        scenario=f"gen-paper-s{index}-d{day}",
        runs={**observers, "robot-tom": run(None if goal is None else goal - 50)},
        day=day,
    )


def test_a_households_later_days_are_one_record_with_their_people_apart() -> None:
    days = [_day(0, 3, 200, 1), _day(0, 4, None, 2)]
    whole = merged(days)
    tom = whole.runs["robot-tom"]
    assert sorted(tom.help) == ["A1@d3", "A1@d4"], sorted(tom.help)
    assert tom.ticks_to_goal == {"A1@d3": 150, "A1@d4": 300}, "an unreached goal counts at the day's end"
    assert tom.help["A1@d4"].goal_tick == 300 and tom.ticks == 602
    assert whole.runs["btom"].counts.detected == 3 and whole.runs["btom"].counts.stretches == 4


def test_numbers_by_day_and_pooled_over_later_days() -> None:
    records = [_day(i, d, 200 + 10 * i, 1) for i in range(3) for d in range(1, 5)]
    observers = ("btom", "truebelief", "perceptonly", "motion", "btom-fresh")
    summary = by_day(Condition(), records, 4, 1, observers)
    assert summary.later is not None, "every household has days 3 and 4"
    assert sorted(summary.by_day) == ["1", "2", "3", "4"] and summary.later.episodes == 3, (
        "days 3 and 4 of each household pool into one record each"
    )
    tom = summary.later.robot["tom"].ticks_to_goal_any_fb.mean
    assert tom is not None
    assert abs(tom - 160.0) < 1e-9, f"expected (150 + 160 + 170) / 3 over households, got {tom}"
    lines = table(summary, observers)
    assert lines[0].startswith("| day | tom: ticks_to_goal_any_fb") and lines[-1].startswith(f"| {LATER}+ |")
