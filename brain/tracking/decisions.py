"""Which decision a person's tick shows (pure): an event of theirs (take, drop, play, use), or
a step to a neighbouring cell; nothing for a tick without either, or a jump."""

from __future__ import annotations

from collections.abc import Sequence

from protocol import Event, EventKind

from ..model.planner import TAKE, Move, drop_action, play_action, use_action
from ..model.world import MOVE_STEPS, WorldModel


def decided_action(
    model: WorldModel, agent: str, before: int, cell: int, events: Sequence[Event]
) -> int | None:
    """The action index ``agent`` took this tick, from cell index ``before`` to ``cell``
    (:mod:`brain.model.planner`'s numbering), or ``None`` when the tick shows no decision."""
    K = model.n_items
    for event in events:
        if event.actor != agent:
            continue
        if event.kind is EventKind.TAKE and event.item in model.items:
            return TAKE + model.items.index(event.item)
        if event.kind is EventKind.DROP:
            return drop_action(K)
        if event.kind is EventKind.PLAY:
            return play_action(K)
        if event.kind is EventKind.USE and event.item in model.items:
            return use_action(K, model.items.index(event.item))
    if cell == before:
        return None
    old, new = model.cells[before], model.cells[cell]
    delta = (int(new[0] - old[0]), int(new[1] - old[1]))
    if delta in MOVE_STEPS:
        return Move(MOVE_STEPS.index(delta)).value
    return None  # a jump (a reset, a lost tick): no decision to explain
