"""Likely deceptions, read off nested beliefs (pure): person A moved an item that person B
wants while A believes B did not see it (A's picture of B still has the item where it was).

The robot reads such a move as a likely deception (``mind.robots[].deceptions``, and a
``deception`` row in ``events.csv``), and with ``RobotSettings.on_deception = "tell"`` it tells
B where the item is rather than putting it back behind A's back.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

import numpy as np

from ..settings import RobotSettings
from .choice import inform_chosen, put_back_chosen
from .situation import Inform, PutBack, Situation, inform_tasks, put_back_tasks


@dataclass(frozen=True)
class Deception:
    """``mover`` moved ``item``, which ``person`` most probably wants, believing they did not
    see: ``p`` is P(the mover believes the person still believes it where it was) x P(the
    person wants it)."""

    mover: str
    person: str
    item: str
    p: float


def deceptions(snap: Situation, settings: RobotSettings) -> Iterator[Deception]:
    """The moves that still stand (the item rests where its mover put it) and read as
    deceptions: the mover believes, at least ``settings.deception_threshold`` probably, that
    the person still believes the item where it was, and it is what the person most
    probably wants."""
    model, nested = snap.model, snap.nested
    if nested is None or nested.values is None:
        return
    for item, (source, target, mover) in snap.moves.items():
        location, holder = snap.item(item)
        if holder is not None or location != target or source not in model.locations:
            continue
        k, s = model.items.index(item), model.locations.index(source)
        for person in snap.people:
            est = snap.estimates.get(person)
            if person == mover or est is None or (mover, person) not in nested.pairs:
                continue
            unseen = float(nested.locations(mover, person)[k, s])
            if unseen >= settings.deception_threshold and int(np.argmax(est.preference)) == k:
                yield Deception(mover=mover, person=person, item=item, p=unseen * float(est.preference[k]))


def deceived_tasks(snap: Situation, settings: RobotSettings) -> Iterator[Inform]:
    """With ``on_deception = "tell"``: tell each deceived person who probably holds a false
    belief about the item where it is now, wherever they are heading."""
    if settings.on_deception != "tell":
        return
    for d in deceptions(snap, settings):
        est = snap.estimates[d.person]
        if est.false_belief[snap.model.items.index(d.item)] >= settings.belief_threshold:
            yield Inform(person=d.person, item=d.item, location=snap.item(d.item)[0] or "")


def inform_or_deceived(snap: Situation, settings: RobotSettings) -> Iterator[Inform]:
    """The ``tom`` inform branch's tasks (the paper's thresholds):
    :func:`~brain.robot.situation.inform_tasks`, then :func:`deceived_tasks`."""
    yield from inform_tasks(snap, settings)
    yield from deceived_tasks(snap, settings)


def put_back_unless_deceived(snap: Situation, settings: RobotSettings) -> Iterator[PutBack]:
    """The ``tom`` put-back branch's tasks: :func:`~brain.robot.situation.put_back_tasks`, less
    the items of likely deceptions when the robot tells the deceived instead."""
    yield from _unless_deceived(put_back_tasks(snap, settings), snap, settings)


def benefit_inform(snap: Situation, settings: RobotSettings) -> Iterator[Inform]:
    """The ``benefit`` policy's informs: those worth doing
    (:func:`~brain.robot.choice.inform_chosen`), then :func:`deceived_tasks`."""
    yield from inform_chosen(snap, settings)
    yield from deceived_tasks(snap, settings)


def benefit_put_back(snap: Situation, settings: RobotSettings) -> Iterator[PutBack]:
    """The ``benefit`` policy's put-backs: those worth doing
    (:func:`~brain.robot.choice.put_back_chosen`), less the items of likely deceptions when
    the robot tells the deceived instead."""
    yield from _unless_deceived(put_back_chosen(snap, settings), snap, settings)


def _unless_deceived(tasks: Iterator[PutBack], snap: Situation, settings: RobotSettings) -> Iterator[PutBack]:
    deceived = {d.item for d in deceptions(snap, settings)} if settings.on_deception == "tell" else set()
    yield from (task for task in tasks if task.item not in deceived)
