"""The robot's side of the brain: from the tracker's estimates and the world to commands.

:class:`RobotBrain` keeps who left which item where, builds the tree's snapshot each tick,
ticks the tree, and hands back the commands to send; statuses from the engine come back
through :meth:`RobotBrain.record`. No I/O: the node sends and receives. The ``oracle`` policy's
robot acts on the minds its ``minds`` source gives (the engine's truth,
:mod:`brain.robot.oracle`) instead of the tracker's.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Mapping

from protocol import (
    AgentKind,
    CommandStatus,
    Event,
    EventKind,
    LikelyDeception,
    RobotActivity,
    RobotCommand,
    State,
)

from ..model.arrays import FloatArray
from ..model.estimates import Estimate
from ..settings import RobotSettings
from ..tracking.tracker import MindTracker
from .deception import deceptions
from .situation import Situation
from .tree import RobotTree


class RobotBrain:
    """Decides what the robot does, given a :class:`MindTracker` that follows the people."""

    def __init__(
        self,
        tracker: MindTracker,
        robot: str,
        settings: RobotSettings | None = None,
        minds: Callable[[State], Mapping[str, Estimate]] | None = None,
    ) -> None:
        spec = next(a for a in tracker.scene.agents if a.id == robot)
        self.minds = minds
        """Where the minds the robot acts on come from, given the tick's state, in place of the
        tracker's estimates (a person it leaves out keeps theirs): the ``oracle`` policy's truth."""
        self.tracker = tracker
        self.robot = robot
        self.tree = RobotTree(robot, (spec.home.col, spec.home.row), settings)
        """The tree of ``settings.policy`` (:mod:`brain.robot.tree`)."""
        self.owners: dict[str, str] = {}
        self.takers: dict[str, str] = {}
        self.taken_from: dict[str, str] = {}
        self.moves: dict[str, tuple[str, str, str]] = {}
        """Item -> ``(from, to, mover)`` of the last time a person took it from one spot and
        put it down at another."""
        self.people = {a.id for a in tracker.scene.agents if a.kind is AgentKind.PERSON}
        self.before_out: dict[str, FloatArray] = {}
        """Person -> ``(K,)`` their want over the items the last tick they were not heading out."""
        self.asked: dict[str, tuple[int, float]] = {}
        """Person -> ``(questions, time)``: how often the robot asked them what they are looking
        for, and the engine time of the last question (its ``ask`` events)."""

    def observe(self, events: Iterable[Event]) -> None:
        """Remember who left each item where: the person who put it down, unless it was
        then moved by someone else (who took it from there and put it elsewhere); and whom the
        robot asked what they are looking for, when."""
        for event in events:
            if event.kind is EventKind.ASK and event.actor == self.robot and event.target in self.people:
                self.asked[event.target] = (self.asked.get(event.target, (0, 0.0))[0] + 1, event.time)
            if event.item is None or event.actor not in self.people:
                continue
            if event.kind is EventKind.TAKE:
                self.takers[event.item] = event.actor
                if event.location is not None:
                    self.taken_from[event.item] = event.location
            elif event.kind is EventKind.DROP:
                source = self.taken_from.pop(event.item, None)
                if source is not None and event.location is not None and source != event.location:
                    self.moves[event.item] = (source, event.location, event.actor)
                owner = self.owners.get(event.item)
                moved_by_another = (
                    owner is not None and owner != event.actor and self.takers.get(event.item) == event.actor
                )
                if not moved_by_another:
                    self.owners[event.item] = event.actor

    def tick(self, state: State) -> list[RobotCommand]:
        """Tick the tree on the world as it is now; return the commands to send."""
        estimates = {p: e for p in self.tracker.people if (e := self.tracker.online(p)) is not None}
        if self.minds is not None:
            estimates |= self.minds(state)
        for person, est in estimates.items():
            items = est.preference[:-1]
            if est.preference[-1] < 0.5 and items.sum() > 0:
                self.before_out[person] = items / items.sum()
        snapshot = Situation(
            scene=self.tracker.scene,
            model=self.tracker.model,
            state=state,
            estimates=estimates,
            owners=self.owners,
            moved_from={p: t.moved_from for p, t in self.tracker.tracks.items()},
            moves=self.moves,
            nested=self.tracker.nested,
            robot=self.robot,
            where=self.where(),
            asked=self.asked,
            before_out=self.before_out,
            answer_reliability=self.tracker.settings.answer_reliability,
        )
        self.tree.tick(snapshot)
        return self.tree.context.book.drain()

    def where(self) -> FloatArray | None:
        """``(K, L)`` the robot's P(each item rests at each location), over the world it
        cannot see (``None``: it sees everything): :meth:`MindTracker.where`."""
        return self.tracker.where()

    def record(self, status: CommandStatus) -> None:
        """A status from the engine."""
        self.tree.context.book.record(status)

    def activity(self) -> RobotActivity:
        """What the robot is doing, once per tick: a task that ended is told once."""
        ctx = self.tree.context
        ended, ctx.ended = ctx.ended, None
        read = deceptions(ctx.snapshot, ctx.settings) if ctx.snapshot is not None else ()
        return RobotActivity(
            robot=self.robot,
            task=ctx.activity,
            detail=ctx.detail,
            utterance=ctx.utterance,
            ended=ended,
            deceptions=tuple(LikelyDeception(d.mover, d.person, d.item, round(d.p, 6)) for d in read),
        )
