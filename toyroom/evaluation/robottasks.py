"""The tasks an acting robot began and did not finish, from its brain's minds (pure).

A robot task (``RobotActivity.task``: an inform, a put-back, a swap, a look, a question) ends
with a ``TaskEnd`` on the tick it ends: ``done``, or ``dropped`` with its reason (most often
"no longer needed": the person took the item, or got where they were going, before the
robot's word or put-back landed). A task that is still running at the episode's last mind
did not finish either. Going home and idling are not tasks. The counts are per run; a
begun task is one that ended or was running at the end (``begun = done + dropped +
running``)."""

from __future__ import annotations

from collections.abc import Mapping

import msgspec

NOT_TASKS = frozenset({"idle", "go home"})
"""Activities that are not tasks (``brain.robot.behaviours``: the robot at or going home)."""


class TaskTally(msgspec.Struct, frozen=True):
    """One run's robot tasks: how many ended done, ended dropped, and were still running at
    the end (every robot of the run together)."""

    done: int = 0
    dropped: int = 0
    running: int = 0

    @property
    def begun(self) -> int:
        return self.done + self.dropped + self.running

    @property
    def unfinished(self) -> int:
        """Begun and not done: dropped, or still running when the episode ended."""
        return self.dropped + self.running


def task_tally(minds: Mapping[int, object]) -> TaskTally:
    """Count the robot tasks of a run's minds (by tick; minds without robots count none). An
    end is counted once where consecutive ticks repeat it."""
    done = dropped = 0
    last_end: dict[str, tuple[str, str, str] | None] = {}
    doing: dict[str, str] = {}
    for tick in sorted(minds):
        for robot in getattr(minds[tick], "robots", ()):
            doing[robot.robot] = robot.task
            end = robot.ended
            key = None if end is None else (end.task, end.detail, str(_value(end.outcome)))
            if key is not None and key != last_end.get(robot.robot):
                if key[2] == "done":
                    done += 1
                else:
                    dropped += 1
            last_end[robot.robot] = key
    running = sum(task not in NOT_TASKS for task in doing.values())
    return TaskTally(done, dropped, running)


def _value(outcome: object) -> object:
    """An outcome's text (``TaskOutcome`` of a decoded mind, or the log's string)."""
    return getattr(outcome, "value", outcome)
