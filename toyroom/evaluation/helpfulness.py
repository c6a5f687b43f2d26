"""How much a robot helped each simulated person in a run (pure functions over what the
evaluator heard).

- ``false_belief``: whether the person, at some tick, had a false belief about the item they
  wanted then (:func:`protocol.believes_falsely`: their true belief gave its true location
  less than :data:`~protocol.FALSE_BELIEF_MASS` times its likeliest location's): the people
  help is for;
  ``false_belief_tick``: the first such tick; ``goal_tick``: the first tick, from then on,
  they played with that item (``None``: never);
- ``wasted_trips``: arrivals at an item location that their true belief, the tick before,
  gave at least one half of holding the item they wanted, when it did not hold it;
- ``interruptions``: what the robot said to them or asked of them (``say``, ``request``,
  ``ask``; one utterance telling of several items counts once);
- ``acted_tick``: when a robot first acted for them (:attr:`PersonHelp.acted_tick`): with
  ``false_belief_tick`` and ``goal_tick``, where the ticks to the goal went (the loss table).
"""

from __future__ import annotations

from collections.abc import Iterable, Mapping
from dataclasses import dataclass

from protocol import Event, EventKind, Scene, State, Truth, believes_falsely

TRIP_BELIEF = 0.5
"""A trip is made for an item when the person gave the place at least this."""


@dataclass
class PersonHelp:
    """One person's run, as help is measured."""

    false_belief: bool = False
    false_belief_tick: int | None = None
    """The first tick of that false belief (``None``: none)."""
    goal_tick: int | None = None
    """The first tick from the first false belief on that the person played with the item
    the false belief was about (``None``: never, or no false belief)."""
    wasted_trips: int = 0
    interruptions: int = 0
    acted_tick: int | None = None
    """The first tick from the first false belief on that a robot acted for the person on the
    item it was about: spoke to them or asked something of them (``say``, ``request``), took
    the item or gave them something (``None``: never, or no false belief)."""


def helpfulness(
    scene: Scene, states: Mapping[int, State], truths: Mapping[int, Truth], events: Iterable[Event]
) -> dict[str, PersonHelp]:
    """Per person of the truth: :class:`PersonHelp` over the run's ticks."""
    spot_at = {(loc.cell.col, loc.cell.row): loc.id for loc in scene.locations}
    robots = {a.id for a in scene.agents if a.kind.value == "robot"}
    people: dict[str, PersonHelp] = {}
    onset: dict[str, tuple[int, str]] = {}
    """Person -> (tick, item) of their first false belief about what they wanted."""
    ticks = sorted(t for t in truths if t in states)
    previous: dict[str, tuple[tuple[int, int], Truth]] = {}
    for tick in ticks:
        truth, state = truths[tick], states[tick]
        where = {place.item: place.location for place in truth.items}
        resting = {place.item: place.location for place in truth.items if place.held_by is None}
        cells = {a.id: (a.cell.col, a.cell.row) for a in state.agents}
        for mind in truth.agents:
            help_ = people.setdefault(mind.agent, PersonHelp())
            belief = {b.item: {p.id: p.p for p in b.locations} for b in mind.beliefs}
            wanted = belief.get(mind.preference)
            true_place = where.get(mind.preference)
            if wanted is not None and true_place is not None and believes_falsely(wanted, true_place):
                help_.false_belief = True
                help_.false_belief_tick = onset.setdefault(mind.agent, (tick, mind.preference))[0]
            cell = cells.get(mind.agent)
            before = previous.get(mind.agent)
            if cell is not None and before is not None and cell != before[0] and cell in spot_at:
                spot = spot_at[cell]
                old = next((a for a in before[1].agents if a.agent == mind.agent), None)
                old_belief = {b.item: {p.id: p.p for p in b.locations} for b in old.beliefs} if old else {}
                believed = old_belief.get(mind.preference, {}).get(spot, 0.0)
                if believed >= TRIP_BELIEF and resting.get(mind.preference) != spot:
                    help_.wasted_trips += 1
            if cell is not None:
                previous[mind.agent] = (cell, truth)
    spoken: set[tuple[int, str, str, str]] = set()  # one say of several items: one event each
    for event in sorted(events, key=lambda e: e.tick):
        if (
            event.actor in robots
            and event.kind in (EventKind.SAY, EventKind.REQUEST, EventKind.ASK)
            and event.target in people
            and (event.tick, event.actor, event.target, event.kind) not in spoken
        ):
            spoken.add((event.tick, event.actor, event.target, event.kind))
            people[event.target].interruptions += 1
        _acted(people, onset, robots, event)
        start = onset.get(event.actor)
        if (
            event.kind is EventKind.PLAY
            and start is not None
            and event.tick >= start[0]
            and event.item == start[1]
        ):
            if people[event.actor].goal_tick is None:
                people[event.actor].goal_tick = event.tick
    return people


def _acted(
    people: Mapping[str, PersonHelp], onset: Mapping[str, tuple[int, str]], robots: set[str], event: Event
) -> None:
    """Record a robot's first act for a person with a false belief (see ``acted_tick``)."""
    if event.actor not in robots:
        return
    for person, (tick, item) in onset.items():
        help_ = people[person]
        if help_.acted_tick is not None or event.tick < tick:
            continue
        spoke = event.kind in (EventKind.SAY, EventKind.REQUEST, EventKind.ASK, EventKind.GIVE)
        spoke = spoke and event.target == person
        if spoke or (event.kind is EventKind.TAKE and event.item == item):
            help_.acted_tick = event.tick
