"""When a participant's episode is over by the study's terms (:class:`toyroom.play.goal.GoalWatch`,
pure): the goal met only after its ``after`` step, or the time limit; an episode that ran to
its own end is ``timed_out`` when there was a goal, ``ended`` when there was none."""

from __future__ import annotations

from protocol import Cell, Event, Goal, Pose, State, Study, StudyOutcome, Vec2
from protocol.state import AgentState
from toyroom.play.goal import GoalWatch


def _state(time: float, holding: str | None = None, region: str = "S1") -> State:
    me = AgentState(
        id="A1", pose=Pose(x=0.5, y=0.5, theta=0.0), velocity=Vec2(x=0.0, y=0.0),
        cell=Cell(col=0, row=0), region=region, holding=holding,
    )  # fmt: skip
    return State(episode=1, tick=int(time * 10), time=time, agents=(me,), items=())


def _event(kind: str, item: str | None = None, label: str | None = None, actor: str = "A1") -> Event:
    return Event(episode=1, tick=1, time=0.1, kind=kind, actor=actor, item=item, label=label)


def test_holding_the_skate_counts_only_after_the_labelled_step() -> None:
    watch = GoalWatch(Study(reached=Goal(holds="skate", after="4"), time_limit=400), "A1")
    assert watch.on_state(_state(1.0, holding="skate")) is None, "holding the skate at the start is no goal"
    watch.on_event(_event("enter", label="4", actor="A2"))
    assert watch.on_state(_state(2.0, holding="skate")) is None, "another person's label 4 does not count"
    watch.on_event(_event("enter", label="4"))
    assert watch.on_state(_state(3.0)) is None, "not holding the skate yet"
    assert watch.on_state(_state(4.0, holding="skate")) is StudyOutcome.GOAL_REACHED
    assert watch.reason() == "goal reached"
    assert watch.on_state(_state(500.0)) is StudyOutcome.GOAL_REACHED, "an outcome is kept"


def test_playing_and_entering_goals() -> None:
    plays = GoalWatch(Study(reached=Goal(plays="ball")), "A1")
    plays.on_event(_event("play", item="skate"))
    assert plays.on_state(_state(1.0)) is None, "playing with the skate is not playing with the ball"
    plays.on_event(_event("play", item="ball"))
    assert plays.on_state(_state(2.0)) is StudyOutcome.GOAL_REACHED
    enters = GoalWatch(Study(reached=Goal(enters="O")), "A1")
    assert enters.on_state(_state(1.0, region="E")) is None
    assert enters.on_state(_state(2.0, region="O")) is StudyOutcome.GOAL_REACHED


def test_the_time_limit_ends_the_episode_timed_out() -> None:
    watch = GoalWatch(Study(reached=Goal(holds="skate"), time_limit=30.0), "A1")
    assert watch.on_state(_state(29.9)) is None
    assert watch.on_state(_state(30.0)) is StudyOutcome.TIMED_OUT
    assert watch.reason() == "the time limit of 30 s was reached before the goal", watch.reason()


def test_an_episode_that_ends_on_its_own_is_timed_out_with_a_goal_and_ended_without() -> None:
    with_goal = GoalWatch(Study(reached=Goal(holds="skate")), "A1")
    assert with_goal.finish() is StudyOutcome.TIMED_OUT
    assert with_goal.reason() == "the episode ended before the goal was reached", with_goal.reason()
    no_goal = GoalWatch(Study(instructions="Walk about."), "A1")
    assert no_goal.on_state(_state(9999.0)) is None, "no goal and no limit: only the episode's own end"
    assert no_goal.finish() is StudyOutcome.ENDED and no_goal.reason() == "the episode ended"
    assert GoalWatch(None, "A1").finish() is StudyOutcome.ENDED
