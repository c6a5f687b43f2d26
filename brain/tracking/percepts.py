"""What a person perceives in one world the tracker follows: sight, then the robot's speech
to them (it told them where an item is, or who holds it). Pure; no I/O."""

from __future__ import annotations

from collections.abc import Sequence

from protocol import Event, EventKind

from ..model.belief import Percept, percept, told
from ..model.world import WorldModel, held_value, value_of


def person_percept(
    model: WorldModel,
    agent: str,
    cell: int,
    held: int,
    truth: tuple[int, ...],
    events: Sequence[Event],
    carriers: Sequence[int],
) -> Percept:
    """What ``agent`` on cell index ``cell``, holding ``held`` (0 nothing, else item index +
    1), perceives in a world of item values ``truth`` (``carriers``: per item, its carrier's
    cell or -1), the tick's ``events`` holding what the robot said."""
    seen = percept(model, cell, truth, held - 1 if held else None, carriers)
    for event in events:  # speech: the robot told this person where an item is or who holds it
        if event.kind is EventKind.SAY and event.target == agent and event.item in model.items:
            k = model.items.index(event.item)
            if event.location in model.locations:
                seen = told(seen, k, value_of(model.locations.index(event.location)))
            elif event.detail.startswith("occupied by "):
                seen = told(seen, k, held_value(truth[k]))
    return seen
