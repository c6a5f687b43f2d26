"""False beliefs that behaviour reveals, read off the truth channel (pure functions).

A tick is *revealed* for a person and item when the person is after the item (their
``pursuit.item``), heading for or searching a place (``pursuit.location``) that their own
belief gives it, and it is not there: a false belief about it (:func:`protocol.believes_falsely`:
their belief gives its true place less than :data:`~protocol.FALSE_BELIEF_MASS` times the
likeliest place's). Any observer who watches them could
then tell that they believe it elsewhere; nothing else shows such a belief when it formed out
of sight (a word the robot did not hear, an item overlooked in view, a belief from before).

A *stretch* is a run of consecutive revealed ticks for one person, item and place in which
the person takes at least :data:`MIN_MOVES` steps before reaching the place (a pursuit that
ends before the person has moved, say because a plan is dropped at once, shows nothing to
anyone). It is detected when the observer's P(false belief) for that person and item passes 0.5 before the
person reaches the place (stands on or next to it), in time for a robot to help; its lead is
how many ticks before that. ``revealed_detection_any`` counts it detected when the observer
reads the person as heading for a place where they falsely believe *some* wanted item rests
(:func:`heading_wrong` above 0.5), whichever item: a walk to an empty place shows that the
person believes something they want is there, not which item.

A false belief is *knowable* at a tick when the robot could know of it: it began with a move
(cause ``moved``: the robot perceived the move), or a pursuit has revealed it (from the
stretch's first revealed tick on, for as long as the false belief lasts).
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass

from protocol import AgentMind, Mind, Truth, believes_falsely

from .scoredminds import ScoredAgent, ScoredMind

MIN_MOVES = 2
"""Steps (cells entered) a person must take in a stretch, before reaching its place, for it to
count: a decision or two is the least any observer of behaviour needs."""
Cell = tuple[int, int]
Key = tuple[str, str]
"""``(person, item)``."""


@dataclass(frozen=True)
class Stretch:
    """A run of revealed ticks: ``person`` after ``item``, heading for ``location`` where it
    is not, from tick ``first`` to ``last``; ``deadline``: the tick they reached the place
    (or ``last + 1`` when they never did); detection counts before it."""

    person: str
    item: str
    location: str
    first: int
    last: int
    deadline: int


def revealed(truth: Truth) -> dict[Key, str]:
    """``(person, item)`` -> the place of each revealed pursuit at this tick."""
    where = {place.item: place.location for place in truth.items}
    out: dict[Key, str] = {}
    for mind in truth.agents:
        pursuit = mind.pursuit
        if pursuit is None or pursuit.item is None or pursuit.location is None:
            continue
        true = where.get(pursuit.item)
        belief = {p.id: p.p for b in mind.beliefs if b.item == pursuit.item for p in b.locations}
        if true is None or pursuit.location == true or not believes_falsely(belief, true):
            continue
        if belief.get(pursuit.location, 0.0) > 0.0:
            out[(mind.agent, pursuit.item)] = pursuit.location
    return out


def stretches(
    truths: Mapping[int, Truth],
    cells: Mapping[int, Mapping[str, Cell]],
    spots: Mapping[str, Cell],
) -> list[Stretch]:
    """Every stretch of revealed ticks, in order of their first tick.

    Args:
        truths: the truth by tick.
        cells: tick -> person -> cell (from the engine's states), to see when they reach a place.
        spots: location id -> its cell.
    """
    open_: dict[Key, tuple[str, int, int, int | None]] = {}
    done: list[Stretch] = []

    def close(key: Key) -> None:
        location, first, last, reached = open_.pop(key)
        deadline = reached if reached is not None else last + 1
        walked = {cells[t][key[0]] for t in range(first, deadline) if key[0] in cells.get(t, {})}
        if len(walked) > MIN_MOVES:
            done.append(Stretch(key[0], key[1], location, first, last, deadline))

    for tick in sorted(truths):
        now = revealed(truths[tick])
        for key in [k for k, (loc, *_) in open_.items() if now.get(k) != loc]:
            close(key)
        for key, location in now.items():
            location_, first, _, reached = open_.get(key, (location, tick, tick, None))
            cell, spot = cells.get(tick, {}).get(key[0]), spots.get(location)
            near = (
                cell is not None and spot is not None and abs(cell[0] - spot[0]) + abs(cell[1] - spot[1]) <= 1
            )
            open_[key] = (location, first, tick, reached if reached is not None or not near else tick)
    for key in list(open_):
        close(key)
    return sorted(done, key=lambda s: (s.first, s.person, s.item))


def knowable(
    truths: Mapping[int, Truth], causes: Mapping[int, Mapping[Key, str]], found: list[Stretch]
) -> dict[int, set[Key]]:
    """Tick -> the false beliefs the robot could know of then (see the module docstring):
    ``causes`` by :func:`~toyroom.evaluation.metrics.false_belief_causes`, ``found`` by
    :func:`stretches`."""
    starts: dict[Key, list[int]] = {}
    for stretch in found:
        starts.setdefault((stretch.person, stretch.item), []).append(stretch.first)
    out: dict[int, set[Key]] = {}
    shown: set[Key] = set()
    for tick in sorted(truths):
        held = causes.get(tick, {})
        shown &= set(held)
        shown |= {key for key in held if tick in starts.get(key, ())}
        out[tick] = {key for key, cause in held.items() if cause == "moved" or key in shown}
    return out


def detection_lead(minds: Mapping[int, Mind | ScoredMind], stretch: Stretch) -> int | None:
    """Ticks from the observer's first flag of ``stretch``'s false belief (P above 0.5, in
    the stretch) to the person reaching the place; ``None`` when not flagged before then."""
    for tick in range(stretch.first, stretch.deadline):
        mind = minds.get(tick)
        agent = next((a for a in mind.agents if a.agent == stretch.person), None) if mind else None
        if agent is not None and stretch.item in agent.false_beliefs:
            return stretch.deadline - tick
    return None


def detection_lead_any(
    minds: Mapping[int, Mind | ScoredMind], stretch: Stretch, truths: Mapping[int, Truth]
) -> int | None:
    """Ticks from the observer's first reading of ``stretch``'s person as heading for a place
    where they falsely believe a wanted item rests (:func:`heading_wrong` of the stretch's
    place above 0.5, in the stretch) to the person reaching it; ``None`` when not before then.
    Item-agnostic: which item they are after need not be known."""
    for tick in range(stretch.first, stretch.deadline):
        mind, truth = minds.get(tick), truths.get(tick)
        agent = next((a for a in mind.agents if a.agent == stretch.person), None) if mind else None
        if agent is None or truth is None:
            continue
        where = {place.item: place.location for place in truth.items}
        if heading_wrong(agent, stretch.location, where) > 0.5:
            return stretch.deadline - tick
    return None


def heading_wrong(agent: AgentMind | ScoredAgent, location: str, where: Mapping[str, str | None]) -> float:
    """The observer's P(the person wants an item they believe rests at ``location``, where it
    does not rest): over the items ``k`` resting elsewhere (``where``: the true resting place
    of each item, ``None`` when carried), P(wants k) x P(believes k at ``location``), each as
    the observer reads them (their product: the observer's marginals). A carried item counts
    neither way, as for the stretches themselves (:func:`revealed`): a belief "at l" of a
    carried one is the brain's "held near l", which may be right."""
    wants = {chance.id: chance.p for chance in agent.preference}
    total = 0.0
    for belief in agent.beliefs:
        if where.get(belief.item) in (location, None):
            continue
        there = next((chance.p for chance in belief.locations if chance.id == location), 0.0)
        total += wants.get(belief.item, 0.0) * there
    return total
