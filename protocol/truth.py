"""Simulated people's true minds, on ``engine/truth`` (optional capability ``truth``).

For evaluation only: a brain subscribes to it only for the ``oracle`` robot policy
(:class:`protocol.Policy`), an upper bound that acts on these true minds.
"""

from __future__ import annotations

from typing import Annotated

import msgspec

from .message import Id, Message, Tick
from .mind import ItemBelief, NestedBelief


class Pursuit(msgspec.Struct, frozen=True):
    """What a person is doing now (protocol 1.2): the ``item`` they are going to take (none:
    they are after no item: going out, putting something down, wandering, playing) and the
    item ``location`` they are heading for or searching (none: a place that is not an item
    location, such as the outside or a random cell)."""

    item: Id | None = None
    location: Id | None = None


class TrueMind(msgspec.Struct, frozen=True):
    """A simulated person's true belief over each item's location, true preference and,
    optionally (protocol 1.2), what they are doing now."""

    agent: Id
    beliefs: tuple[ItemBelief, ...]
    preference: Id
    """The item they want, or ``out``."""
    pursuit: Pursuit | None = None
    """Their current plan, when the engine knows it (an evaluator reads *revealed* false
    beliefs off it: after an item, heading for a place where it is not)."""
    nested: tuple[NestedBelief, ...] = ()
    """Protocol 1.3: per other person, where this person believes that one believes each item
    is, when the engine models it (by the protocol's "who sees whom")."""


class ItemPlace(msgspec.Struct, frozen=True):
    """Where ``item`` truly is: a location id (a carried item counts at its carrier's
    location, see ``protocol.carry``), and who holds it, if anyone."""

    item: Id
    location: Id
    held_by: Id | None = None


class Truth(Message, frozen=True, kw_only=True, tag="truth"):
    """True minds of every simulated person at engine tick ``tick``, and where every item
    truly is (so an evaluator can score beliefs from this channel alone)."""

    episode: Annotated[int, msgspec.Meta(ge=0)]
    tick: Tick
    agents: tuple[TrueMind, ...]
    items: tuple[ItemPlace, ...] = ()
