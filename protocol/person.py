"""A person's command (``person/<id>/command``, a participant's page -> engine): a human
drives one person of the scene instead of its script (``toyroom play``).

Optional for engines: an engine that does not offer puppets ignores the key. An engine that
does (sim2d: ``--puppet ID``) carries each command out on its next tick, as it would a
scripted person's step, and emits the same events (``take``, ``drop``, ``play``, ``stop``,
``reply``). Every command also records the key the participant pressed and when, so a
recording holds the participant's key presses and their times.
"""

from __future__ import annotations

import enum
from typing import Annotated

import msgspec

from .message import Id, Message


class PersonAction(enum.Enum):
    """What the participant asks their person to do."""

    MOVE = "move"
    """Step one cell in ``direction`` (a walkable neighbour; a wall: nothing happens)."""
    GOTO = "goto"
    """Walk the shortest way to ``target``: a location id (its cell) or a region id (its nearest cell)."""
    STOP = "stop"
    """Stop at the next cell centre."""
    TAKE = "take"
    """Take ``item`` (or, without one, any item resting within reach: same or 4-neighbouring cell)."""
    DROP = "drop"
    """Put the carried item down at the location within reach."""
    PLAY = "play"
    """Start playing with the carried item where the person stands, or stop when playing."""
    ACCEPT = "accept"
    """Say yes to the robot's open question: a ``request`` (hand over, or swap), a ``give``, or
    an ``ask`` about an item; to an open ``ask`` ("what are you looking for?", from 1.6),
    name the item wanted in ``item``."""
    DECLINE = "decline"
    """Say no to the robot's open question (to an open ``ask``: nothing)."""


class Direction(enum.Enum):
    """A grid direction: ``up`` is +row (north on the map), ``right`` is +col."""

    UP = "up"
    DOWN = "down"
    LEFT = "left"
    RIGHT = "right"


STEP_OF: dict[Direction, tuple[int, int]] = {
    Direction.UP: (0, 1),
    Direction.DOWN: (0, -1),
    Direction.LEFT: (-1, 0),
    Direction.RIGHT: (1, 0),
}
"""The ``(dcol, drow)`` of each direction."""


class PersonCommand(Message, frozen=True, kw_only=True, tag="person_command"):
    """Person ``person`` is asked to do ``action`` (protocol 1.4, optional).

    ``seq`` counts the participant's commands from 0 (an engine may drop a repeated one);
    ``key`` is the key the participant pressed (the browser's ``KeyboardEvent.key``, e.g.
    ``"ArrowUp"``, ``"t"``; empty when not from a keyboard) and ``pressed`` when, in seconds
    since the participant's page opened (``toyroom play`` counts a reloaded page on from the
    page before, so the times never run back); ``participant`` names the participant.
    """

    person: Id
    action: PersonAction
    seq: Annotated[int, msgspec.Meta(ge=0)] = 0
    direction: Direction | None = None
    """For ``move``."""
    target: Id | None = None
    """For ``goto``: a location or region id."""
    item: Id | None = None
    """For ``take``: the item (``None``: any within reach); for ``accept`` of an open ``ask``:
    the item the person wants."""
    key: str = ""
    pressed: Annotated[float, msgspec.Meta(ge=0.0)] = 0.0
    participant: str = ""

    def __post_init__(self) -> None:
        if self.action is PersonAction.MOVE and self.direction is None:
            raise ValueError("person_command 'move' needs field 'direction'")
        if self.action is PersonAction.GOTO and self.target is None:
            raise ValueError("person_command 'goto' needs field 'target'")
