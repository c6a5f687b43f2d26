"""Help measures on a tiny episode computed by hand, and their pooled means and intervals."""

from __future__ import annotations

import msgspec
import pytest

from protocol import (
    AgentKind,
    AgentSpec,
    Cell,
    Event,
    EventKind,
    ItemBelief,
    ItemPlace,
    Prob,
    TrueMind,
    Truth,
)
from tests.scenes import tiny_scene, tiny_state
from toyroom.evaluation.aggregate import aggregate, robot_losses, robot_metrics
from toyroom.evaluation.helpfulness import helpfulness
from toyroom.evaluation.intervals import cuts, pooled_means
from toyroom.evaluation.records import EpisodeRecord
from toyroom.evaluation.report import _tables
from toyroom.evaluation.summary import TickLosses


def truth(tick: int, believes_b: float, ball_at: str = "A") -> Truth:
    mind = TrueMind(
        agent="p",
        beliefs=(ItemBelief(item="ball", locations=(Prob("A", 1 - believes_b), Prob("B", believes_b))),),
        preference="ball",
    )
    return Truth(episode=1, tick=tick, agents=(mind,), items=(ItemPlace(item="ball", location=ball_at),))


def test_a_wasted_trip_a_false_belief_and_an_interruption_by_hand() -> None:
    """p stands in the doorway believing the ball is in B (it is in A: a false belief), walks
    to B (a wasted trip: B had 1.0 of their belief, the ball is not there), is told by the
    robot, walks to A (no trip wasted: the ball is there)."""
    scene = msgspec.structs.replace(
        tiny_scene(), agents=(*tiny_scene().agents, AgentSpec(id="r", kind=AgentKind.ROBOT, home=Cell(1, 0)))
    )
    cells = {1: (3, 0), 2: (2, 0), 3: (1, 0), 4: (0, 0)}
    states = {t: tiny_state(t, c, "A") for t, c in cells.items()}
    truths = {1: truth(1, 1.0), 2: truth(2, 1.0), 3: truth(3, 0.0), 4: truth(4, 0.0)}
    said = Event(
        episode=1, tick=2, time=1.4, kind=EventKind.SAY, actor="r", target="p", item="ball", location="A"
    )
    by_person = Event(
        episode=1, tick=3, time=2.1, kind=EventKind.SAY, actor="p", target="r", item="ball", location="A"
    )
    played = Event(episode=1, tick=4, time=2.8, kind=EventKind.PLAY, actor="p", item="ball", location="A")
    help_ = helpfulness(scene, states, truths, [said, by_person, played])["p"]
    assert (help_.false_belief, help_.wasted_trips, help_.interruptions) == (True, 1, 1), help_
    assert help_.goal_tick == 4, "the first play with the ball after the false belief began"
    assert help_.false_belief_tick == 1, f"the false belief began at tick 1, got {help_.false_belief_tick}"
    assert help_.acted_tick == 2, (
        f"the robot first acted for p when it spoke at tick 2, got {help_.acted_tick}"
    )
    alone = helpfulness(scene, states, truths, [by_person, played])["p"]
    assert alone.acted_tick is None, f"p speaking to the robot is not the robot acting: {alone.acted_tick}"
    also = msgspec.structs.replace(said, item="skate", location="B")  # the same utterance (1.6)
    later = msgspec.structs.replace(said, tick=3, time=2.1)
    help_ = helpfulness(scene, states, truths, [said, also, later, played])["p"]
    assert help_.interruptions == 2, (
        f"a say of two items is one interruption, a later say another: expected 2, got {help_.interruptions}"
    )
    asked = Event(episode=1, tick=2, time=1.4, kind=EventKind.ASK, actor="r", target="p")
    help_ = helpfulness(scene, states, truths, [asked, later, played])["p"]
    assert (help_.interruptions, help_.acted_tick) == (2, 2), (
        f"a question is an interruption and an act for p: expected 2 interruptions, acted at tick 2, "
        f"got {help_.interruptions}, {help_.acted_tick}"
    )


def test_no_false_belief_no_trip_wasted() -> None:
    states = {1: tiny_state(1, (1, 0), "A"), 2: tiny_state(2, (0, 0), "A")}
    help_ = helpfulness(tiny_scene(), states, {1: truth(1, 0.0), 2: truth(2, 0.0)}, [])["p"]
    assert (help_.false_belief, help_.wasted_trips, help_.interruptions) == (False, 0, 0), help_


def _episode(runs: dict[str, dict]) -> EpisodeRecord:
    """An episode of these runs (as ``episodes.json`` has them; what they leave out, empty)."""
    empty = {"counts": {}, "outcome": {}, "ticks_to_goal": {}, "episode_ticks": 0, "ticks": 0}
    runs = {key: {**empty, **run} for key, run in runs.items()}
    return EpisodeRecord.from_builtins({"index": 0, "map": "paper", "scenario": "s", **runs})


def test_pooled_means_and_paired_differences() -> None:
    per_episode = {"tom": [(10.0, 1), (30.0, 2), (0.0, 0)], "none": [(20.0, 1), (50.0, 2), (0.0, 0)]}
    bounds, differences = pooled_means(per_episode, seed=1, resamples=200)
    assert bounds["tom"]["mean"] == pytest.approx(40 / 3) and bounds["none"]["mean"] == pytest.approx(70 / 3)
    assert differences["none"]["mean"] == pytest.approx(-10.0)
    assert differences["none"]["hi"] < 0, f"tom is below none in every resample: {differences}"


def test_robot_metrics_count_only_people_with_false_beliefs_for_ticks_to_goal() -> None:
    def run(fb: bool, tick: int | None, trips: int) -> dict:
        return {
            "outcome": {"A1": tick is not None},
            "ticks_to_goal": {"A1": tick},
            "episode_ticks": 100,
            "help": {
                "A1": {
                    "false_belief": fb,
                    "false_belief_tick": 10 if fb else None,
                    "goal_tick": tick if fb else None,
                    "wasted_trips": trips,
                    "interruptions": 0,
                }
            },
        }

    episodes = [
        _episode({"robot-tom": run(True, 40, 0), "btom": run(True, None, 2)}),
        _episode({"robot-tom": run(False, 10, 1), "btom": run(False, 10, 1)}),
    ]
    policies, differences = robot_metrics(episodes, seed=1)
    assert policies["tom"].ticks_to_goal_fb.mean == 40 and policies["none"].ticks_to_goal_fb.mean == 100
    assert policies["tom"].wasted_trips.mean == 0.5 and policies["none"].wasted_trips.mean == 1.5
    assert policies["tom"].success == 1.0 and policies["none"].success == 0.5
    assert differences["none"].ticks_to_goal_fb.mean == -60
    since = {p: policies[p].ticks_from_false_belief.mean for p in ("tom", "none")}
    assert since == {"tom": 30, "none": 90}, f"expected ticks from the false belief's tick 10, got {since}"


def test_ticks_to_goal_any_fb_scores_the_same_people_under_every_policy() -> None:
    """A robot that spares A1 a false belief (A1 has the item at tick 30 instead of 80) drops
    A1 from its own run's ``ticks_to_goal_fb``, and one that causes A2 a false belief adds A2
    there; over the people mistaken in any run, each is scored in every run."""

    def run(fb: dict[str, bool], reached: dict[str, int | None]) -> dict:
        help_ = {
            a: {
                "false_belief": fb[a],
                "false_belief_tick": 10 if fb[a] else None,
                "goal_tick": reached[a] if fb[a] else None,
                "wasted_trips": 0,
                "interruptions": 0,
            }
            for a in fb
        }
        return {"outcome": {}, "ticks_to_goal": reached, "episode_ticks": 100, "help": help_}

    episode = _episode(
        {
            "robot-tom": run({"A1": False, "A2": False, "A3": False}, {"A1": 30, "A2": 50, "A3": 20}),
            "robot-tidy": run({"A1": True, "A2": True, "A3": False}, {"A1": 80, "A2": None, "A3": 20}),
            "btom": run({"A1": True, "A2": False, "A3": False}, {"A1": 80, "A2": 50, "A3": 20}),
        }
    )
    policies, differences = robot_metrics([episode], seed=1)
    own = {p: policies[p].ticks_to_goal_fb.mean for p in ("tom", "tidy", "none")}
    assert own == {"tom": None, "tidy": 90, "none": 80}, f"each run's own people: {own}"
    every = {p: policies[p].ticks_to_goal_any_fb.mean for p in ("tom", "tidy", "none")}
    assert every == {"tom": 40, "tidy": 90, "none": 65}, f"A1 and A2 in every run (never: 100): {every}"
    assert differences["none"].ticks_to_goal_any_fb.mean == -25, differences["none"]


def test_the_loss_table_splits_the_ticks_to_the_goal() -> None:
    def run(acted: int | None) -> dict:
        person = {"false_belief": True, "false_belief_tick": 10, "goal_tick": 40, "acted_tick": acted}
        return {"episode_ticks": 100, "help": {"A1": person, "A2": {"false_belief": False}}}

    losses = robot_losses([_episode({"robot-tom": run(25), "btom": run(None)})])
    assert losses["tom"] == TickLosses(
        before_false_belief=10, before_robot_acted=15, after_robot_acted=15, robot_acted=1.0
    ), losses["tom"]
    assert losses["none"] == TickLosses(
        before_false_belief=10, before_robot_acted=30, after_robot_acted=0, robot_acted=0.0
    ), f"a robot that never acted: the whole wait is before it acted, got {losses['none']}"


def test_cuts_and_shares_of_the_oracle_by_hand() -> None:
    """Pooled means: none 300/3 = 100 ticks, tom 240/3 = 80, oracle 180/3 = 60. tom cuts
    (100 - 80) / 100 = 0.2, the oracle 0.4; tom's share of the oracle's cut is 20 / 40 = 0.5."""
    per_episode = {
        "tom": [(90.0, 1), (150.0, 2)],
        "oracle": [(60.0, 1), (120.0, 2)],
        "none": [(100.0, 1), (200.0, 2)],
    }
    got = cuts(per_episode, seed=1, base="none", oracle="oracle", resamples=200)
    assert set(got) == {"tom", "oracle"}, "none is the base: no cut of its own"
    assert got["tom"]["cut"]["mean"] == pytest.approx(0.2) and got["oracle"]["cut"]["mean"] == pytest.approx(
        0.4
    )
    assert got["tom"]["share_of_oracle"]["mean"] == pytest.approx(0.5), got["tom"]
    assert got["oracle"]["share_of_oracle"]["mean"] == pytest.approx(1.0), got["oracle"]
    tom = got["tom"]["share_of_oracle"]
    assert tom["lo"] is not None and tom["lo"] <= 0.5 <= tom["hi"], f"a paired interval around 0.5: {tom}"
    flat = {**per_episode, "oracle": per_episode["none"]}  # an oracle that cuts nothing
    got = cuts(flat, seed=1, base="none", oracle="oracle", resamples=50)
    assert got["tom"]["share_of_oracle"]["mean"] is None and got["tom"]["cut"]["mean"] == pytest.approx(0.2)
    alone = cuts({"tom": per_episode["tom"], "none": per_episode["none"]}, seed=1, base="none")
    assert alone["tom"]["share_of_oracle"]["mean"] is None, "no oracle ran: no share"


def test_the_robot_table_gives_cuts_and_marks_the_oracle() -> None:
    """One person with a false belief: none reaches the goal at tick 100 (never: the episode's
    length), tom at 70, the oracle at 40: tom cuts 0.3, the oracle 0.6, tom's share is 0.5."""

    def run(goal: int | None) -> dict:
        person = {"false_belief": True, "false_belief_tick": 10, "goal_tick": goal}
        return {"episode_ticks": 100, "ticks_to_goal": {"A1": goal}, "help": {"A1": person}}

    episode = _episode({"robot-tom": run(70), "robot-oracle": run(40), "btom": run(None)})
    policies, _ = robot_metrics([episode], seed=1)
    assert list(policies) == ["tom", "oracle", "none"], list(policies)
    for key in ("cut", "cut_any_fb"):
        assert getattr(policies["tom"], key).mean == pytest.approx(0.3), (key, policies["tom"])
        assert getattr(policies["oracle"], key).mean == pytest.approx(0.6), (key, policies["oracle"])
    for key in ("share_of_oracle", "share_of_oracle_any_fb"):
        assert getattr(policies["tom"], key).mean == pytest.approx(0.5), (key, policies["tom"])
    assert policies["none"].cut is None and policies["none"].share_of_oracle is None
    table = "\n".join(_tables(msgspec.structs.replace(aggregate([], 1, ("btom",)), robot=policies)))
    row = next(line for line in table.splitlines() if line.startswith("| oracle (reads true minds) |"))
    cells = [cell.split(" [")[0] for cell in row.strip("| ").split(" | ")]
    assert cells[-4:] == ["0.600", "1.000", "0.600", "1.000"], f"cut, share, on both measures: {row}"
    assert "| policy | success |" in table and "share_of_oracle_any_fb |" in table, table
    assert "upper bound, not a robot one could build" in table, "the report says what the oracle is"
