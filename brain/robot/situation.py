"""What the robot could do, read off the estimates and the world (pure functions).

In the priority order of the paper's Section IV.B:
1. :func:`find_inform`: a person heads for an item that is not where they believe it is.
2. :func:`find_occupied`: a person's preferred item is held by someone else (and they are
   heading for where they believe it is).
3. :func:`find_put_back`: an item was moved while the person who left it was away.
Each yields every such task it sees; the robot's context picks the first not skipped (done or
given up) and called for long enough (``RobotContext.ready``), and :func:`still_needed` checks
a task against the world as it is now.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass

import numpy as np

from protocol import AgentKind, Scene, State

from ..model.arrays import FloatArray
from ..model.estimates import Estimate
from ..model.nested import NestedBeliefs
from ..model.world import WorldModel
from ..settings import RobotSettings
from .benefit import put_back_late, put_back_lengthens, put_back_walk


@dataclass(frozen=True)
class Inform:
    """Tell ``person`` that ``item`` is at ``location``, and in the same utterance where the
    items of ``also`` are (``(item, location)`` pairs: a tell of several items,
    :func:`brain.robot.benefit.tell_worth`). A task is the same task whatever ``also`` says
    (it is chosen afresh each tick: the items worth naming may change on the way)."""

    person: str
    item: str
    location: str
    also: tuple[tuple[str, str], ...] = dataclasses.field(default=(), compare=False)


@dataclass(frozen=True)
class Occupied:
    """``person`` wants ``item``, which ``holder`` has: tell them, and ask for a swap for ``offer``."""

    person: str
    item: str
    holder: str
    offer: str | None


@dataclass(frozen=True)
class PutBack:
    """Put ``item`` back at ``location`` for ``owner``, who believes it is there; ``why``
    says where that belief comes from, for the task's text (``"where mia left it"``)."""

    item: str
    location: str
    owner: str
    why: str = ""


@dataclass(frozen=True)
class Look:
    """Go and see whether ``item`` rests at ``location``, so as to tell ``person`` where it is
    (the robot cannot rule out other places: :mod:`brain.robot.benefit`)."""

    item: str
    location: str
    person: str


@dataclass(frozen=True)
class AskWhat:
    """Ask ``person`` what they are looking for (an open question: protocol 1.6's ``ask``),
    so as to help them with what they answer (:func:`brain.robot.benefit.ask_worth`);
    ``round``: how often the robot has asked them before (a later question is a new task)."""

    person: str
    round: int = 0


Task = Inform | Occupied | PutBack | Look | AskWhat


@dataclass(frozen=True)
class Situation:
    """Everything the robot's decisions read, at one tick."""

    scene: Scene
    model: WorldModel
    state: State
    estimates: Mapping[str, Estimate]
    owners: Mapping[str, str]
    """Item id -> the person who last put it down."""
    moved_from: Mapping[str, int | None]
    """Person id -> the cell index they left on their last move (``None``: not moved yet)."""
    moves: Mapping[str, tuple[str, str, str]] = dataclasses.field(default_factory=dict)
    """Item id -> ``(from, to, mover)``: the last time a person moved it from spot to spot."""
    nested: NestedBeliefs | None = None
    """What each person believes the others believe (:mod:`brain.model.nested`)."""
    robot: str | None = None
    """The robot's id (``None``: no robot decides on this snapshot)."""
    where: FloatArray | None = None
    """``(K, L)`` the robot's own P(item ``k`` rests at location ``l``) over the branches of the
    world it cannot see (``None``: it sees everything, and ``state`` says where items are)."""
    asked: Mapping[str, tuple[int, float]] = dataclasses.field(default_factory=dict)
    """Person id -> ``(questions, time)``: how often the robot has asked them what they are
    looking for, and the engine time (s) of the last question."""
    before_out: Mapping[str, FloatArray] = dataclasses.field(default_factory=dict)
    """Person id -> ``(K,)`` what they wanted, over the items (normalised), the last tick they
    were not heading out (P(out) below one half): the want an errand out ends in."""
    answer_reliability: float = 0.9
    """P(a person's answer is true), as the brain's model reads answers
    (:attr:`brain.settings.ModelSettings.answer_reliability`)."""

    @property
    def people(self) -> list[str]:
        return [a.id for a in self.scene.agents if a.kind is AgentKind.PERSON]

    def approaching(self, person: str, location: int) -> bool:
        """Whether ``person`` is at (or next to) location index ``location``, or their last
        move brought them closer to it."""
        cell = next(
            (
                self.model.cell_index.get((a.cell.col, a.cell.row))
                for a in self.state.agents
                if a.id == person
            ),
            None,
        )
        if cell is None:
            return False
        now = self.model.distance[location, cell]
        before = self.moved_from.get(person)
        return bool(now <= 1 or (before is not None and now < self.model.distance[location, before]))

    def holding(self, agent: str) -> str | None:
        """The item ``agent`` holds now, if any."""
        return next((a.holding for a in self.state.agents if a.id == agent), None)

    def item(self, item_id: str) -> tuple[str | None, str | None]:
        """Where an item is now: ``(resting location, holder)``."""
        for item in self.state.items:
            if item.id == item_id:
                return item.location, item.held_by
        return None, None


def inform_tasks(snap: Situation, settings: RobotSettings) -> Iterator[Inform]:
    """People with empty hands who do not know where the free item they want is, told where
    it is: heading for where they probably falsely believe it (a false belief at least
    ``belief_threshold``, their intention at least ``intention_threshold``), or searching (they
    most likely want it, their belief gives its true place less than ``inform_mass``, and
    they are on the move but not towards it: after a place found empty, ignorance is not a
    false belief, but telling still saves the search)."""
    model = snap.model
    for person in snap.people:
        est = snap.estimates.get(person)
        if est is None or snap.holding(person) is not None:
            continue
        k, believed, p = est.intention
        if k is not None and believed is not None and p >= settings.intention_threshold:
            item = model.items[k]
            location, holder = snap.item(item)
            mistaken = est.false_belief[k] >= settings.belief_threshold
            if holder is None and location is not None and model.locations[believed] != location:
                if mistaken and snap.approaching(person, believed):
                    yield Inform(person=person, item=item, location=location)
                    continue
        searching = _searching(snap, settings, person, est)
        if searching is not None:
            yield searching


def _searching(snap: Situation, settings: RobotSettings, person: str, est: Estimate) -> Inform | None:
    """The inform for ``person`` when they search for the free item they most likely want
    without knowing where it is (see :func:`inform_tasks`), else ``None``."""
    model = snap.model
    d = int(np.argmax(est.preference))
    if d >= model.n_items or est.preference[d] < settings.preference_threshold:
        return None
    item = model.items[d]
    location, holder = snap.item(item)
    if holder is not None or location is None or est.false_belief[d] >= settings.belief_threshold:
        return None
    true = model.locations.index(location)
    if est.beliefs[d, true] >= settings.inform_mass or snap.moved_from.get(person) is None:
        return None
    if snap.approaching(person, true):
        return None
    return Inform(person=person, item=item, location=location)


def occupied_tasks(snap: Situation, settings: RobotSettings) -> Iterator[Occupied]:
    """People with empty hands who most likely want an item another person holds, and are
    heading for where they believe it is; the swap offers the holder the free item they most
    probably want (their inferred desire, not the order of the items). Not when the person
    knows who holds it (no false belief about it) and the holder most likely declines (their
    preference for the offer below ``swap_accept``): that would interrupt both for nothing."""
    model = snap.model
    people = set(snap.people)
    for person in snap.people:
        est = snap.estimates.get(person)
        if est is None or snap.holding(person) is not None:
            continue
        d = int(np.argmax(est.preference))
        if d >= model.n_items or est.preference[d] < settings.preference_threshold:
            continue
        item = model.items[d]
        _, holder = snap.item(item)
        if holder is None or holder == person or holder not in people:
            continue
        if not snap.approaching(person, int(np.argmax(est.beliefs[d]))):
            continue  # they are not looking for it (yet)
        free = [i for i in model.items if i != item and snap.item(i)[1] is None and snap.item(i)[0]]
        holder_est = snap.estimates.get(holder)
        if holder_est is not None:  # offer what the holder most probably wants of what is free
            free.sort(key=lambda i: -float(holder_est.preference[model.items.index(i)]))
        offer = free[0] if free else None
        accept = (
            0.0 if holder_est is None or offer is None else holder_est.preference[model.items.index(offer)]
        )
        if est.false_belief[d] < settings.belief_threshold and accept < settings.swap_accept:
            continue  # they know who has it, and the holder would most likely say no: nothing to gain
        yield Occupied(person=person, item=item, holder=holder, offer=offer)


def put_back_tasks(snap: Situation, settings: RobotSettings) -> Iterator[PutBack]:
    """Items resting where someone who will look for them probably does not believe (a false
    belief at least ``belief_threshold`` probable), to be put back at their most probable
    believed location: the person who left the item there, or, for an item nobody left
    (the scene placed it), anyone but the person who moved it who may want it (preference at
    least ``put_back_preference``). Not when it would mislead someone else who may want it and
    believes it where it is now (belief times preference at least ``put_back_harm``), nor when
    it would serve the person worse than leaving it (:func:`_worse_than_leaving`): it lies on
    their way to where they believe it, or where they use it, or the robot would put it there
    only after they could have looked."""
    model = snap.model
    for k, item in enumerate(model.items):
        location, holder = snap.item(item)
        if holder is not None or location is None:
            continue
        mover = snap.moves[item][2] if item in snap.moves else None
        owner = snap.owners.get(item)
        looking = [owner] if owner is not None and owner != mover else [p for p in snap.people if p != mover]
        found = None
        for person in looking:
            est = snap.estimates.get(person)
            if est is None or est.false_belief[k] < settings.belief_threshold:
                continue
            believed = int(np.argmax(est.beliefs[k]))
            if model.locations[believed] == location:
                continue
            if person != owner and est.preference[k] < settings.put_back_preference:
                continue
            found = (person, model.locations[believed])
            break
        if found is None or misled(snap, k, location, found[0]) >= settings.put_back_harm:
            continue
        if _worse_than_leaving(snap, found[0], location, found[1], settings):
            continue
        yield PutBack(item=item, location=found[1], owner=found[0], why=_believed_why(snap, item, *found))


def _worse_than_leaving(
    snap: Situation, person: str, location: str, believed: str, settings: RobotSettings
) -> bool:
    """Whether putting an item back from ``location`` at ``believed`` would serve ``person``
    worse than leaving it: it lengthens their way to it
    (:func:`~brain.robot.benefit.put_back_lengthens`: it lies on their way, or nearer where
    they use it), or it would land after they could reach ``believed``
    (:func:`~brain.robot.benefit.put_back_late`: they would look there first and search on;
    not while they are outside, away on an errand, when the paper's robot tidies). ``False``
    when the robot does not see them."""
    model = snap.model
    cells = {a.id: model.cell_index.get((a.cell.col, a.cell.row)) for a in snap.state.agents}
    cell, robot = cells.get(person), cells.get(snap.robot) if snap.robot is not None else None
    if cell is None:
        return False
    t, b = model.locations.index(location), model.locations.index(believed)
    if put_back_lengthens(model, cell, t, b, settings.search_factor):
        return True
    if robot is None or model.outside[cell]:
        return False  # away (an errand): not on their way to it now
    return put_back_late(model, put_back_walk(model, robot, t, b), cell, b, settings.put_back_slack)


def _believed_why(snap: Situation, item: str, person: str, location: str) -> str:
    """Where ``person``'s belief that ``item`` is at ``location`` comes from, as a task's text
    says it: they put it down there (and it was moved from there since), or only believe it."""
    moved_from = snap.moves[item][0] if item in snap.moves else None
    if snap.owners.get(item) == person and moved_from == location:
        return f"where {person} left it"
    return f"where {person} believes it is"


def misled(snap: Situation, k: int, location: str, helped: str) -> float:
    """How much moving item ``k`` away from ``location`` would mislead the others: the most,
    over people other than ``helped``, of P(they believe it there) x P(they want it)."""
    where = snap.model.locations.index(location)
    harms = [
        float(est.beliefs[k, where] * est.preference[k])
        for person, est in snap.estimates.items()
        if person != helped
    ]
    return max(harms, default=0.0)


def tidy_tasks(snap: Situation, settings: RobotSettings) -> Iterator[PutBack]:
    """The ``tidy`` policy (no theory of mind): every item a person moved from one spot to
    another, still resting where they put it, goes back where it was."""
    for item, (source, target, mover) in snap.moves.items():
        location, holder = snap.item(item)
        if holder is None and location == target:
            yield PutBack(
                item=item, location=source, owner=mover, why=f"where it was before {mover} moved it"
            )


def announce_tasks(snap: Situation, settings: RobotSettings) -> Iterator[Inform]:
    """The ``announce`` policy (no theory of mind): after every move, tell every other person
    where the item is now."""
    for item, (_, target, mover) in snap.moves.items():
        location, holder = snap.item(item)
        if holder is not None or location != target:
            continue
        for person in snap.people:
            if person != mover:
                yield Inform(person=person, item=item, location=target)


Finder = Callable[[Situation, RobotSettings], Iterator[Task]]


def still_needed(finder: Finder, task: Task, snap: Situation, settings: RobotSettings) -> bool:
    """Whether ``finder`` still sees ``task`` in the world as it is now."""
    return any(candidate == task for candidate in finder(snap, settings))


def why_unneeded(task: Task, snap: Situation, settings: RobotSettings) -> str:
    """Why a begun ``task`` is no longer called for, in words for ``events.csv``: the first of
    the checks its finder makes that the world as it is now fails."""
    if isinstance(task, AskWhat):
        if snap.holding(task.person) is not None:
            return f"{task.person} is carrying the {snap.holding(task.person)}"
        return f"asking {task.person} is no longer worth more than helping them as they are"
    item = task.item
    location, holder = snap.item(item)
    if isinstance(task, Look):
        return f"looking at {task.location} is no longer worth more than telling {task.person} now"
    person = task.owner if isinstance(task, PutBack) else task.person
    est = snap.estimates.get(person)
    k = snap.model.items.index(item)
    if isinstance(task, Occupied):
        if holder != task.holder:
            return f"{task.holder} no longer has the {item}"
    elif holder is not None:
        return f"{holder} took the {item}"
    elif isinstance(task, Inform) and location != task.location:
        return f"the {item} is no longer at {task.location}"
    if snap.holding(person) is not None:
        return f"{person} is carrying the {snap.holding(person)}"
    if est is not None and est.false_belief[k] < settings.belief_threshold and not isinstance(task, Occupied):
        return f"{person} probably knows where the {item} is now"
    if isinstance(task, PutBack) and location is not None:
        if misled(snap, k, location, person) >= settings.put_back_harm:
            return f"putting the {item} back would mislead someone who believes it at {location}"
    if not isinstance(task, PutBack):
        return f"{person} is no longer heading for the {item}"
    return f"{person} probably no longer believes the {item} at {task.location}"
