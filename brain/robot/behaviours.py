"""The robot tree's behaviours (py_trees): find a task for a branch, carry a branch through,
send one command and follow its statuses, go home when there is nothing to do."""

from __future__ import annotations

from collections.abc import Callable

import py_trees
from py_trees.common import Access, Status

from protocol import Cell, Navigate, Request, TaskEnd, TaskOutcome

from ..settings import RobotSettings
from .context import RobotContext, Skip, Step
from .situation import AskWhat, Finder, Inform, Look, Occupied, Task, why_unneeded


def _client(behaviour: py_trees.behaviour.Behaviour, namespace: str) -> py_trees.blackboard.Client:
    """The behaviour's blackboard client: ``context`` registered for writing, as every
    behaviour here changes its fields (the task, the activity, the commands sent)."""
    client = behaviour.attach_blackboard_client(name=behaviour.name, namespace=namespace)
    client.register_key(key="context", access=Access.WRITE)
    return client


class FindTask(py_trees.behaviour.Behaviour):
    """Succeeds when its finder has a task (or this branch's task is under way)."""

    def __init__(self, name: str, branch: str, finder: Finder, namespace: str) -> None:
        super().__init__(name)
        self.branch = branch
        self.finder = finder
        self.board = _client(self, namespace)

    def update(self) -> Status:
        ctx: RobotContext = self.board.context
        if ctx.snapshot is None:
            return Status.FAILURE
        if ctx.task is not None:
            return Status.SUCCESS if ctx.branch == self.branch else Status.FAILURE
        task = ctx.ready(self.branch, self.finder)
        if task is None:
            return Status.FAILURE
        ctx.task, ctx.branch, ctx.finder, ctx.unneeded_since = task, self.branch, self.finder, None
        ctx.attempts[task] += 1
        ctx.activity, ctx.detail = self.branch, describe(task)
        self.feedback_message = ctx.detail
        return Status.SUCCESS


class TaskBranch(py_trees.composites.Sequence):
    """A task's sequence; when it ends, the task is released (and marked done on success)."""

    def __init__(self, name: str, namespace: str, children: list[py_trees.behaviour.Behaviour]) -> None:
        super().__init__(name=name, memory=True, children=children)
        self.board = _client(self, namespace)

    def terminate(self, new_status: Status) -> None:
        super().terminate(new_status)
        ctx: RobotContext = self.board.context
        if ctx.branch == self.name and new_status in (Status.SUCCESS, Status.FAILURE, Status.INVALID):
            if new_status is Status.SUCCESS and ctx.task is not None:
                ctx.done.add(ctx.task)
            if ctx.task is not None and new_status is not Status.INVALID:
                done = new_status is Status.SUCCESS
                outcome = TaskOutcome.DONE if done else TaskOutcome.DROPPED
                reason = "" if done else _failure(self)
                ctx.ended = TaskEnd(task=self.name, detail=describe(ctx.task), outcome=outcome, reason=reason)
            ctx.task, ctx.branch, ctx.finder = None, None, None


def _failure(behaviour: py_trees.behaviour.Behaviour) -> str:
    """Why a failed subtree failed: the step that failed, and what it said."""
    step = behaviour
    while isinstance(step, py_trees.composites.Composite) and step.current_child is not None:
        step = step.current_child
    said = step.feedback_message
    return f"{step.name}: {said}" if said else f"{step.name} failed"


class Act(py_trees.behaviour.Behaviour):
    """One command: sent when the step starts, then followed until it ends or times out.

    ``make(context)`` builds the action (``Skip.SKIP``: nothing to do; ``None``: impossible).
    A ``request`` succeeds only when the person answers yes. A ``guarded`` step gives up
    (cancelling its command) as soon as its task is no longer called for, e.g. the person
    it walks to has turned away.
    """

    def __init__(
        self,
        name: str,
        make: Callable[[RobotContext], Step],
        namespace: str,
        *,
        timeout: Callable[[RobotSettings], float] = lambda s: s.action_timeout,
        says: Callable[[RobotContext], str] | None = None,
        guarded: bool = False,
    ) -> None:
        super().__init__(name)
        self.guarded = guarded
        self.make = make
        self.timeout = timeout
        self.says = says
        self.board = _client(self, namespace)
        self.command: str | None = None
        self.outcome: Status | None = None
        self.started = 0.0

    def initialise(self) -> None:
        ctx: RobotContext = self.board.context
        if ctx.homing is not None:
            ctx.book.cancel(ctx.homing)
            ctx.homing = None
        self.command, self.outcome = None, None
        self.started = ctx.now
        action = self.make(ctx)
        if action is Skip.SKIP:
            self.outcome = Status.SUCCESS
        elif action is None:
            self.outcome = Status.FAILURE
            self.feedback_message = "impossible now"
        else:
            self.command = ctx.book.send(action)
            if self.says is not None:
                ctx.utterance = self.says(ctx)

    def update(self) -> Status:
        if self.outcome is not None:
            return self.outcome
        ctx: RobotContext = self.board.context
        assert self.command is not None
        status = ctx.book.status(self.command)
        if self.guarded and (status is None or not status.state.final) and ctx.give_up():
            ctx.book.cancel(self.command)
            why = why_unneeded(ctx.task, ctx.snapshot, ctx.settings) if ctx.task and ctx.snapshot else ""
            self.feedback_message = f"no longer needed ({why})" if why else "no longer needed"
            return Status.FAILURE
        if status is None or not status.state.final:
            if ctx.now - self.started > self.timeout(ctx.settings):
                ctx.book.cancel(self.command)
                self.feedback_message = "timed out"
                return Status.FAILURE
            return Status.RUNNING
        self.feedback_message = f"{status.state.value} {status.reason}".strip()
        if not ctx.book.succeeded(status):
            return Status.FAILURE
        if isinstance(ctx.book.sent[self.command].action, Request) and status.answer is not True:
            return Status.FAILURE
        return Status.SUCCESS

    def terminate(self, new_status: Status) -> None:
        if new_status is Status.INVALID and self.command is not None:
            ctx: RobotContext = self.board.context
            ctx.book.cancel(self.command)


class GoHome(py_trees.behaviour.Behaviour):
    """Nothing to do: go back to the home cell (and give way as soon as there is a task)."""

    def __init__(self, namespace: str) -> None:
        super().__init__("go home")
        self.board = _client(self, namespace)

    def update(self) -> Status:
        ctx: RobotContext = self.board.context
        if ctx.cell_of(ctx.robot) == ctx.home:
            ctx.activity, ctx.detail = "idle", "at home"
            return Status.SUCCESS
        ctx.activity, ctx.detail = "go home", f"to ({ctx.home[0]},{ctx.home[1]})"
        if ctx.homing is None or ctx.book.final(ctx.homing):
            if ctx.homing is not None and not ctx.book.succeeded(ctx.book.status(ctx.homing)):
                ctx.homing = None
                return Status.FAILURE
            ctx.homing = ctx.book.send(Navigate(cell=Cell(*ctx.home)))
        return Status.RUNNING

    def terminate(self, new_status: Status) -> None:
        ctx: RobotContext = self.board.context
        if new_status is Status.INVALID and ctx.homing is not None:
            ctx.book.cancel(ctx.homing)
            ctx.homing = None


def describe(task: Task) -> str:
    """A one-line description of a task."""
    if isinstance(task, Inform):
        rest = "".join(f", the {item} at {location}" for item, location in task.also)
        return f"tell {task.person} the {task.item} is at {task.location}{rest}"
    if isinstance(task, AskWhat):
        return f"ask {task.person} what they are looking for"
    if isinstance(task, Look):
        return f"look whether the {task.item} is at {task.location}, to tell {task.person}"
    if isinstance(task, Occupied):
        offer = f" for the {task.offer}" if task.offer else ""
        return f"{task.person} wants the {task.item} {task.holder} has: ask for a swap{offer}"
    return f"put the {task.item} back at {task.location}, {task.why or 'for ' + task.owner}"
