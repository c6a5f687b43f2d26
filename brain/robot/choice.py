"""What the ``tom`` robot chooses to do: every candidate task scored by its expected benefit
(:mod:`brain.robot.benefit`), the best one per person and item kept when it is worth doing.

Candidates, for each person with empty hands and each item resting where the robot knows (or
can guess) it is:

- **inform** them where it is (:class:`~brain.robot.situation.Inform`): one tell per person,
  naming every item whose word is worth its cost (:func:`~brain.robot.benefit.tell_worth`);
- **put it back** where they believe it (:class:`~brain.robot.situation.PutBack`), when the
  robot is sure where it rests;
- **look** first at the likeliest place (:class:`~brain.robot.situation.Look`), when the robot
  cannot rule out other places and looking is worth more than guessing;
- **ask** them what they are looking for (:class:`~brain.robot.situation.AskWhat`), when what
  the answer would teach is worth more than the interruption
  (:func:`~brain.robot.benefit.ask_worth`), and not within ``ask_again_after`` of asking them.

Swaps (:func:`~brain.robot.situation.occupied_tasks`) and the ``tidy`` and ``announce``
baselines keep their own rules. Pure: a snapshot in, tasks out (one pass per snapshot, shared
by the tree's branches).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable, Iterator
from dataclasses import dataclass

import numpy as np

from ..model.answers import open_answers
from ..model.estimates import Estimate
from ..model.world import ABSENT
from ..settings import RobotSettings
from .benefit import (
    Worth,
    ask_worth,
    cell_distances,
    inform_worth,
    lasting_preference,
    look_or_guess,
    put_back_walk,
    put_back_worth,
    tell_worth,
)
from .situation import AskWhat, Inform, Look, PutBack, Situation, Task, _believed_why

SURE = 0.999
"""The robot treats an item's place as known when it gives it at least this."""


@dataclass(frozen=True)
class Scored:
    """A candidate task and what it is expected to be worth (steps)."""

    task: Task
    worth: Worth


_LAST: tuple[Situation, RobotSettings, list[Scored]] | None = None


def chosen(snap: Situation, settings: RobotSettings) -> list[Scored]:
    """The tasks worth doing now (net worth above 0), the best per person and item, best
    first (computed once per snapshot and settings)."""
    global _LAST
    if _LAST is not None and _LAST[0] is snap and _LAST[1] is settings:
        return _LAST[2]
    key, snap = snap, _lasting(snap) if settings.lasting_want else snap
    best = _best(candidates(snap, settings))
    for asked in questions(snap, settings, best):
        assert isinstance(asked.task, AskWhat)
        best[(asked.task.person, "?")] = asked
    kept = sorted((s for s in best.values() if s.worth.net > 0), key=lambda s: -s.worth.net)
    _LAST = (key, settings, kept)
    return kept


def _lasting(snap: Situation) -> Situation:
    """``snap`` with every person's preference as help weighs it under ``lasting_want``
    (:func:`~brain.robot.benefit.lasting_preference`: an errand out ends in the want they set
    out with)."""
    minds = {
        person: dataclasses.replace(
            est, preference=lasting_preference(est.preference, snap.before_out.get(person))
        )
        for person, est in snap.estimates.items()
    }
    return dataclasses.replace(snap, estimates=minds)


def _best(scored: Iterator[Scored]) -> dict[tuple[str, str], Scored]:
    """The best of ``scored`` per person (a put-back's owner) and item."""
    best: dict[tuple[str, str], Scored] = {}
    for one in scored:
        task = one.task
        assert not isinstance(task, AskWhat)
        key = (task.owner if isinstance(task, PutBack) else task.person, task.item)
        if key not in best or one.worth.net > best[key].worth.net:
            best[key] = one
    return best


def questions(
    snap: Situation, settings: RobotSettings, best: dict[tuple[str, str], Scored] | None = None
) -> Iterator[Scored]:
    """Asking each person with empty hands what they are looking for, scored as the value of
    its answer (:func:`~brain.robot.benefit.ask_worth`): the best help for them after each
    answer, by its odds (``snap.answer_reliability``), against the best help now (read off
    ``best``, :func:`_best` of every candidate now, when the caller has it). Not a person
    asked within ``settings.ask_again_after`` seconds."""
    best = _best(candidates(snap, settings)) if best is None else best
    for person in snap.people:
        est = snap.estimates.get(person)
        if est is None or snap.holding(person) is not None:
            continue
        times, last = snap.asked.get(person, (0, -np.inf))
        if snap.state.time - last < settings.ask_again_after:
            continue
        odds, after = open_answers(est.preference, snap.answer_reliability)
        helped = [_help(snap, settings, person, dataclasses.replace(est, preference=p)) for p in after]
        now = _net(s for (whom, _), s in best.items() if whom == person)
        yield Scored(AskWhat(person, times), ask_worth(odds, np.array(helped), now, settings))


def _help(snap: Situation, settings: RobotSettings, person: str, est: Estimate) -> float:
    """The net worth of the robot's best help for ``person`` were their mind ``est`` (0 when
    nothing is worth doing)."""
    mind = dataclasses.replace(snap, estimates={**snap.estimates, person: est})
    return _net(_best(candidates(mind, settings, only=person)).values())


def _net(scored: Iterable[Scored]) -> float:
    """The best net worth among ``scored`` (0 when there is none)."""
    return max((s.worth.net for s in scored), default=0.0)


def candidates(snap: Situation, settings: RobotSettings, only: str | None = None) -> Iterator[Scored]:
    """Every inform, put-back and look the robot could do now, scored (``only``: for that
    person alone)."""
    model = snap.model
    cells = _cells(snap)
    robot = cells.get(snap.robot or "")
    if robot is None:
        return
    steps = cell_distances(model)
    sure: dict[str, list[tuple[int, int, Worth]]] = {}
    for k, item in enumerate(model.items):
        where = _where(snap, k)
        if where is None:
            continue
        for person in snap.people if only is None else [only]:
            est, cell = snap.estimates.get(person), cells.get(person)
            if est is None or cell is None or snap.holding(person) is not None:
                continue
            to_person = max(float(steps[robot, cell]) - 1.0, 0.0)
            if not np.isfinite(to_person):
                continue
            likeliest = int(np.argmax(where))
            if where[likeliest] >= SURE:
                inform = inform_worth(model, est, k, cell, likeliest, to_person, settings)
                sure.setdefault(person, []).append((k, likeliest, inform))
                yield from _put_back(snap, settings, cells, robot, person, k, likeliest)
                continue
            seeing = model.sees[:, likeliest]
            to_look = float(np.min(np.where(seeing, steps[robot], np.inf)))
            if not np.isfinite(to_look):
                continue
            look, guess = look_or_guess(model, est, k, cell, where, to_person, to_look, settings)
            yield Scored(Inform(person, item, model.locations[likeliest]), guess)
            yield Scored(Look(item, model.locations[likeliest], person), look)
    for person, informs in sure.items():
        yield _tell(snap, person, informs, settings)


def _tell(
    snap: Situation, person: str, informs: list[tuple[int, int, Worth]], settings: RobotSettings
) -> Scored:
    """One tell to ``person`` of every item whose word is worth its ``tell_item_cost``
    (``informs``: item, the location it rests at, and the single inform's worth), likeliest
    saving first; with none worth it, the best single inform (not worth doing either)."""
    ranked = sorted(informs, key=lambda i: -i[2].saved)
    named = [i for i in ranked if i[2].saved > settings.tell_item_cost] or ranked[:1]
    places = [(snap.model.items[k], snap.model.locations[t]) for k, t, _ in named]
    task = Inform(person, *places[0], also=tuple(places[1:]))
    return Scored(task, tell_worth([w for _, _, w in named], settings))


def _put_back(
    snap: Situation, settings: RobotSettings, cells: dict[str, int], robot: int, person: str, k: int, t: int
) -> Iterator[Scored]:
    """Putting item ``k`` (resting at ``t``) back where ``person`` most probably believes it,
    unless they moved it there themselves."""
    model = snap.model
    item = model.items[k]
    if item in snap.moves and snap.moves[item][2] == person:
        return
    est = snap.estimates[person]
    believed = int(np.argmax(est.beliefs[k, : model.n_locations]))
    if believed == t or model.locations[believed] == ABSENT:
        return
    walk = put_back_walk(model, robot, t, believed)
    if not np.isfinite(walk):
        return
    worth = put_back_worth(model, snap.estimates, cells, person, k, t, believed, walk, settings)
    why = _believed_why(snap, item, person, model.locations[believed])
    yield Scored(PutBack(item, model.locations[believed], person, why=why), worth)


def _where(snap: Situation, k: int) -> np.ndarray | None:
    """``(L,)`` where the robot believes item ``k`` rests (``None``: carried, or absent)."""
    model = snap.model
    location, holder = snap.item(model.items[k])
    if holder is not None or location is None or location == ABSENT:
        return None
    if snap.where is None:
        where = np.zeros(model.n_locations)
        where[model.locations.index(location)] = 1.0
        return where
    row = snap.where[k]
    if row.sum() <= 0 or (ABSENT in model.locations and row[model.locations.index(ABSENT)] > 0.5):
        return None
    return row


def _cells(snap: Situation) -> dict[str, int]:
    """Every agent's cell index."""
    index = snap.model.cell_index
    return {a.id: c for a in snap.state.agents if (c := index.get((a.cell.col, a.cell.row))) is not None}


def inform_chosen(snap: Situation, settings: RobotSettings) -> Iterator[Inform]:
    """The ``inform`` branch's tasks under ``tom``: the informs worth doing, best first."""
    yield from (s.task for s in chosen(snap, settings) if isinstance(s.task, Inform))


def put_back_chosen(snap: Situation, settings: RobotSettings) -> Iterator[PutBack]:
    """The ``put back`` branch's tasks under ``tom``: the put-backs worth doing, best first."""
    yield from (s.task for s in chosen(snap, settings) if isinstance(s.task, PutBack))


def question_chosen(snap: Situation, settings: RobotSettings) -> Iterator[AskWhat]:
    """The ``ask`` branch's tasks: the questions worth asking, best first."""
    yield from (s.task for s in chosen(snap, settings) if isinstance(s.task, AskWhat))


def look_chosen(snap: Situation, settings: RobotSettings) -> Iterator[Look]:
    """The ``look`` branch's tasks: the looks worth doing, best first."""
    yield from (s.task for s in chosen(snap, settings) if isinstance(s.task, Look))
