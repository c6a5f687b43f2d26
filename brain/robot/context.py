"""What the robot's behaviour tree reads and writes: one :class:`RobotContext` on the tree's
own blackboard namespace (so two brains in one process never share state), and what an
action maker returns (:data:`Step`)."""

from __future__ import annotations

import enum
from collections import Counter
from dataclasses import dataclass, field

from protocol import NEIGHBOURS, Action, Cell, GridCell, Navigate, TaskEnd

from ..settings import RobotSettings
from .commands import CommandBook
from .situation import Finder, Situation, Task, still_needed


class Skip(enum.Enum):
    """An action maker's answer when there is nothing to do: the step succeeds at once."""

    SKIP = "skip"


Step = Action | Skip | None
"""What an action maker returns: the action to send, ``Skip.SKIP``, or ``None`` (impossible now)."""


@dataclass
class RobotContext:
    """Everything the tree reads and writes, on its blackboard under key ``context`` (its
    behaviours register the key for writing: they change its fields)."""

    robot: str
    home: GridCell
    settings: RobotSettings
    book: CommandBook
    snapshot: Situation | None = None
    task: Task | None = None
    branch: str | None = None
    finder: Finder | None = None
    attempts: Counter[Task] = field(default_factory=Counter)
    done: set[Task] = field(default_factory=set)
    homing: str | None = None
    activity: str = "idle"
    detail: str = ""
    utterance: str | None = None
    seen_since: dict[tuple[str, Task], float] = field(default_factory=dict)
    """``(branch, task)`` -> the engine time a finder has seen the task since, tick after tick."""
    unneeded_since: float | None = None
    """The engine time since which the current task has not been called for (:meth:`give_up`)."""
    ended: TaskEnd | None = None
    """The task that ended at this tick (done, or dropped and why), until it is published."""

    @property
    def now(self) -> float:
        return self.snapshot.state.time if self.snapshot is not None else 0.0

    def task_needed(self) -> bool:
        """Whether the current task is still called for by the world as it is now."""
        if self.task is None or self.finder is None or self.snapshot is None:
            return False
        return still_needed(self.finder, self.task, self.snapshot, self.settings)

    def give_up(self) -> bool:
        """Whether to give up the current task: it has not been called for, tick after tick,
        for ``confirm_seconds`` (hysteresis both ways: a blip neither starts nor stops one)."""
        if self.task_needed():
            self.unneeded_since = None
            return False
        if self.unneeded_since is None:
            self.unneeded_since = self.now
        return self.now - self.unneeded_since >= self.settings.confirm_seconds

    def skip(self) -> set[Task]:
        tired = {t for t, n in self.attempts.items() if n >= self.settings.attempts}
        return self.done | tired

    def ready(self, branch: str, finder: Finder) -> Task | None:
        """The first task ``finder`` calls for now that is not skipped (:meth:`skip`) and has
        been called for by it, tick after tick, for ``confirm_seconds`` (hysteresis: a blip of
        the estimates starts nothing). Remembers what it sees now and forgets what it does not;
        one pass of the finder."""
        if self.snapshot is None:
            return None
        skip = self.skip()
        tasks = [task for task in finder(self.snapshot, self.settings) if task not in skip]
        now = self.now
        for key in [k for k in self.seen_since if k[0] == branch and k[1] not in tasks]:
            del self.seen_since[key]
        for task in tasks:
            self.seen_since.setdefault((branch, task), now)
        confirm = self.settings.confirm_seconds
        return next((t for t in tasks if now - self.seen_since[(branch, t)] >= confirm), None)

    def cell_of(self, agent: str) -> GridCell | None:
        assert self.snapshot is not None
        for a in self.snapshot.state.agents:
            if a.id == agent:
                return (a.cell.col, a.cell.row)
        return None

    def holding(self, agent: str) -> str | None:
        assert self.snapshot is not None
        return next((a.holding for a in self.snapshot.state.agents if a.id == agent), None)

    def cell_of_item(self, item: str) -> GridCell | None:
        """Where an item is: its spot, or its carrier's cell."""
        assert self.snapshot is not None
        location, holder = self.snapshot.item(item)
        return self.location_cell(location) if location else self.cell_of(holder or "")

    def location_cell(self, location: str) -> GridCell:
        assert self.snapshot is not None
        loc = next(loc for loc in self.snapshot.scene.locations if loc.id == location)
        return (loc.cell.col, loc.cell.row)

    def near(self, target: GridCell | None) -> Step:
        """A navigation to a cell next to ``target`` (or ``SKIP`` when already within reach)."""
        me = self.cell_of(self.robot)
        if target is None or me is None or self.snapshot is None:
            return None
        if abs(me[0] - target[0]) + abs(me[1] - target[1]) <= 1:
            return Skip.SKIP
        walkable = self.snapshot.model.cell_index
        around = [(target[0] + dc, target[1] + dr) for dc, dr in NEIGHBOURS]
        options = [c for c in around if c in walkable] or [target]
        best = min(options, key=lambda c: (abs(c[0] - me[0]) + abs(c[1] - me[1]), c))
        return Navigate(cell=Cell(*best))
