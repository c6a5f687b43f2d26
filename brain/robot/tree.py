"""The robot's behaviour tree (py_trees), in the paper's priority order:

1. inform: a person heads for an item that is not where they believe: tell them where it is;
2. swap: a person's preferred item is held by someone else: tell them it is occupied, ask
   the holder to swap; on yes, bring each item to the other person; on no, tell the person
   where the other item is;
3. put back: an item was moved while the person who left it was away: bring it back to
   where that person believes it is;
4. go home.

Each action is a command on the wire whose statuses are awaited, with a timeout; a failed
command or a refusal fails its branch, and the next tick the tree chooses again (a task is
tried ``attempts`` times at most, so the tree never sticks). A task, once begun, is carried
through before another begins; going home gives way at once.

The tree reads one :class:`RobotContext` from its own blackboard namespace, so two brains in
one process never share state.
"""

from __future__ import annotations

import uuid
from collections import Counter
from collections.abc import Callable
from dataclasses import dataclass, field

import py_trees
from py_trees.common import Access, Status

from protocol import Action, Cell, Give, Navigate, Pick, Place, Request, Say, SayTopic

from ..settings import RobotSettings
from .commands import CommandBook
from .situation import (
    Finder,
    Inform,
    Occupied,
    PutBack,
    Snapshot,
    Task,
    first_task,
    inform_tasks,
    occupied_tasks,
    put_back_tasks,
    still_needed,
)

GridCell = tuple[int, int]
SKIP = "skip"
"""What an action maker returns when there is nothing to do (the step succeeds at once)."""


@dataclass
class RobotContext:
    """Everything the tree reads and writes, on its blackboard under key ``context``."""

    robot: str
    home: GridCell
    settings: RobotSettings
    book: CommandBook
    snapshot: Snapshot | None = None
    task: Task | None = None
    branch: str | None = None
    finder: Finder | None = None
    attempts: Counter[Task] = field(default_factory=Counter)
    done: set[Task] = field(default_factory=set)
    homing: str | None = None
    activity: str = "idle"
    detail: str = ""
    utterance: str | None = None

    @property
    def now(self) -> float:
        return self.snapshot.state.time if self.snapshot is not None else 0.0

    def task_needed(self) -> bool:
        """Whether the current task is still called for by the world as it is now."""
        if self.task is None or self.finder is None or self.snapshot is None:
            return False
        return still_needed(self.finder, self.task, self.snapshot, self.settings)

    def skip(self) -> set[Task]:
        tired = {t for t, n in self.attempts.items() if n >= self.settings.attempts}
        return self.done | tired

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

    def near(self, target: GridCell | None) -> Action | str | None:
        """A navigation to a cell next to ``target`` (or ``SKIP`` when already within reach)."""
        me = self.cell_of(self.robot)
        if target is None or me is None or self.snapshot is None:
            return None
        if abs(me[0] - target[0]) + abs(me[1] - target[1]) <= 1:
            return SKIP
        walkable = self.snapshot.model.cell_index
        around = [(target[0] + dc, target[1] + dr) for dc, dr in ((0, 1), (0, -1), (-1, 0), (1, 0))]
        options = [c for c in around if c in walkable] or [target]
        best = min(options, key=lambda c: (abs(c[0] - me[0]) + abs(c[1] - me[1]), c))
        return Navigate(cell=Cell(*best))


def _client(behaviour: py_trees.behaviour.Behaviour, namespace: str) -> py_trees.blackboard.Client:
    client = behaviour.attach_blackboard_client(name=behaviour.name, namespace=namespace)
    client.register_key(key="context", access=Access.READ)
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
        task = first_task(self.finder, ctx.snapshot, ctx.settings, ctx.skip())
        if task is None:
            return Status.FAILURE
        ctx.task, ctx.branch, ctx.finder = task, self.branch, self.finder
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
            ctx.task, ctx.branch, ctx.finder = None, None, None


class Act(py_trees.behaviour.Behaviour):
    """One command: sent when the step starts, then followed until it ends or times out.

    ``make(context)`` builds the action (``SKIP``: nothing to do; ``None``: impossible).
    A ``request`` succeeds only when the person answers yes. A ``guarded`` step gives up
    (cancelling its command) as soon as its task is no longer called for, e.g. the person
    it walks to has turned away.
    """

    def __init__(
        self,
        name: str,
        make: Callable[[RobotContext], Action | str | None],
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
        if action == SKIP:
            self.outcome = Status.SUCCESS
        elif action is None or isinstance(action, str):
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
        if self.guarded and not ctx.task_needed() and (status is None or not status.state.final):
            ctx.book.cancel(self.command)
            self.feedback_message = "no longer needed"
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
        return f"tell {task.person} the {task.item} is at {task.location}"
    if isinstance(task, Occupied):
        offer = f" for the {task.offer}" if task.offer else ""
        return f"{task.person} wants the {task.item} {task.holder} has: ask for a swap{offer}"
    return f"put the {task.item} back at {task.location}, where {task.owner} left it"


def _task(ctx: RobotContext) -> Task:
    assert ctx.task is not None
    return ctx.task


def build_tree(namespace: str) -> py_trees.behaviour.Behaviour:
    """The robot's tree; its behaviours read the context at ``<namespace>/context``."""
    ns = namespace
    nav: Callable[[RobotSettings], float] = lambda s: s.navigate_timeout  # noqa: E731

    def occupied(ctx: RobotContext) -> Occupied:
        task = _task(ctx)
        assert isinstance(task, Occupied)
        return task

    def inform(ctx: RobotContext) -> Inform:
        task = _task(ctx)
        assert isinstance(task, Inform)
        return task

    def put_back(ctx: RobotContext) -> PutBack:
        task = _task(ctx)
        assert isinstance(task, PutBack)
        return task

    def offer_action(
        make: Callable[[RobotContext, str], Action | str | None],
    ) -> Callable[[RobotContext], Action | str | None]:
        def build(ctx: RobotContext) -> Action | str | None:
            offer = occupied(ctx).offer
            return SKIP if offer is None else make(ctx, offer)

        return build

    def offer_spot(ctx: RobotContext, offer: str) -> Action | str | None:
        assert ctx.snapshot is not None
        location, holder = ctx.snapshot.item(offer)
        if ctx.holding(ctx.robot) == offer:
            return SKIP
        return ctx.near(ctx.location_cell(location) if location else ctx.cell_of(holder or ""))

    inform_branch = TaskBranch(
        "inform",
        ns,
        [
            FindTask("false belief?", "inform", inform_tasks, ns),
            Act(
                "go to the person",
                lambda c: c.near(c.cell_of(inform(c).person)),
                ns,
                timeout=nav,
                guarded=True,
            ),
            Act(
                "say where it is",
                lambda c: Say(
                    person=inform(c).person,
                    item=inform(c).item,
                    topic=SayTopic.LOCATION,
                    location=inform(c).location,
                ),
                ns,
                says=lambda c: f"{inform(c).person}, the {inform(c).item} is at {inform(c).location}.",
            ),
        ],
    )
    accepted = py_trees.composites.Sequence(
        "swap accepted",
        memory=True,
        children=[
            Act("go to the holder", lambda c: c.near(c.cell_of(occupied(c).holder)), ns, timeout=nav),
            Act(
                "ask for a swap",
                lambda c: Request(person=occupied(c).holder, item=occupied(c).item, offer=occupied(c).offer),
                ns,
                says=lambda c: (
                    f"{occupied(c).holder}, would you give the {occupied(c).item} to "
                    f"{occupied(c).person}" + (f" for the {occupied(c).offer}?" if occupied(c).offer else "?")
                ),
            ),
            Act("go to the person", lambda c: c.near(c.cell_of(occupied(c).person)), ns, timeout=nav),
            Act("give the item", lambda c: Give(person=occupied(c).person), ns),
            Act("go to the offer", offer_action(offer_spot), ns, timeout=nav),
            Act(
                "pick the offer",
                offer_action(lambda c, o: SKIP if c.holding(c.robot) == o else Pick(item=o)),
                ns,
            ),
            Act(
                "go to the holder",
                offer_action(lambda c, o: c.near(c.cell_of(occupied(c).holder))),
                ns,
                timeout=nav,
            ),
            Act("give the offer", offer_action(lambda c, o: Give(person=occupied(c).holder)), ns),
        ],
    )
    declined = py_trees.composites.Sequence(
        "swap declined",
        memory=True,
        children=[
            Act("go to the person", lambda c: c.near(c.cell_of(occupied(c).person)), ns, timeout=nav),
            Act(
                "say where the other item is",
                offer_action(
                    lambda c, o: (
                        Say(
                            person=occupied(c).person,
                            item=o,
                            topic=SayTopic.LOCATION,
                            location=c.snapshot.item(o)[0],
                        )
                        if c.snapshot is not None and c.snapshot.item(o)[0]
                        else SKIP
                    )
                ),
                ns,
                says=lambda c: f"{occupied(c).person}, the {occupied(c).offer} is free.",
            ),
        ],
    )
    swap_branch = TaskBranch(
        "swap",
        ns,
        [
            FindTask("preferred item occupied?", "swap", occupied_tasks, ns),
            Act(
                "go to the person",
                lambda c: c.near(c.cell_of(occupied(c).person)),
                ns,
                timeout=nav,
                guarded=True,
            ),
            Act(
                "say it is occupied",
                lambda c: Say(
                    person=occupied(c).person,
                    item=occupied(c).item,
                    topic=SayTopic.OCCUPIED,
                    holder=occupied(c).holder,
                ),
                ns,
                says=lambda c: (
                    f"{occupied(c).person}, {occupied(c).holder} is playing with the {occupied(c).item}."
                ),
            ),
            py_trees.composites.Selector("ask", memory=True, children=[accepted, declined]),
        ],
    )
    put_back_branch = TaskBranch(
        "put back",
        ns,
        [
            FindTask("moved while away?", "put back", put_back_tasks, ns),
            Act(
                "go to the item",
                lambda c: c.near(c.cell_of_item(put_back(c).item)),
                ns,
                timeout=nav,
                guarded=True,
            ),
            Act("pick it", lambda c: Pick(item=put_back(c).item), ns),
            Act("go to its place", lambda c: c.near(c.location_cell(put_back(c).location)), ns, timeout=nav),
            Act("put it there", lambda c: Place(location=put_back(c).location), ns),
        ],
    )
    return py_trees.composites.Selector(
        "robot", memory=False, children=[inform_branch, swap_branch, put_back_branch, GoHome(ns)]
    )


class RobotTree:
    """A tree, its blackboard namespace and context: what the brain ticks once per step."""

    def __init__(self, robot: str, home: GridCell, settings: RobotSettings | None = None) -> None:
        self.namespace = f"/brain_{uuid.uuid4().hex[:8]}"
        self.context = RobotContext(
            robot=robot, home=home, settings=settings or RobotSettings(), book=CommandBook(robot)
        )
        self.writer = py_trees.blackboard.Client(name="brain", namespace=self.namespace)
        self.writer.register_key(key="context", access=Access.WRITE)
        self.writer.context = self.context
        self.root = build_tree(self.namespace)
        self.root.setup_with_descendants()

    def tick(self, snapshot: Snapshot) -> None:
        """Tick once with the world as it is now."""
        self.context.snapshot = snapshot
        self.root.tick_once()

    def render(self) -> str:
        """The tree as text (``toyroom brain --print-tree``)."""
        return py_trees.display.unicode_tree(self.root)
