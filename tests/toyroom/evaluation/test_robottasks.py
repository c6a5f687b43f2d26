"""The robot tasks an acting run began and did not finish, counted by hand from minds."""

from __future__ import annotations

from toyroom.evaluation.robottasks import TaskTally, task_tally
from toyroom.evaluation.scoredminds import ScoredEnd, ScoredMind, ScoredRobot


def mind(tick: int, task: str, ended: tuple[str, str] | None = None) -> ScoredMind:
    end = None if ended is None else ScoredEnd(task=ended[0], detail="the ball", outcome=ended[1])
    return ScoredMind(tick=tick, agents=(), robots=(ScoredRobot(robot="robot", task=task, ended=end),))


def test_done_dropped_and_running_at_the_end_by_hand() -> None:
    minds = {
        0: mind(0, "idle"),
        1: mind(1, "put back"),
        2: mind(2, "go home", ("put back", "done")),
        3: mind(3, "inform"),
        4: mind(4, "idle", ("inform", "dropped")),
        5: mind(5, "idle", ("inform", "dropped")),  # the same end heard again: counted once
        6: mind(6, "swap"),
    }
    tally = task_tally(minds)
    assert tally == TaskTally(done=1, dropped=1, running=1), (
        f"expected 1 done, 1 dropped, 1 running, got {tally}"
    )
    assert (tally.begun, tally.unfinished) == (3, 2), f"expected 3 begun, 2 unfinished, got {tally}"


def test_a_robot_at_home_or_without_robots_began_nothing() -> None:
    assert task_tally({0: mind(0, "idle"), 1: mind(1, "go home")}) == TaskTally()
    assert task_tally({0: ScoredMind(tick=0, agents=())}) == TaskTally()
