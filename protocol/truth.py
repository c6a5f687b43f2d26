"""Simulated people's true minds, on ``engine/truth`` (optional capability ``truth``).

For evaluation only: a brain never subscribes to it.
"""

from __future__ import annotations

from typing import Annotated

import msgspec

from .message import Id, Message, Tick
from .mind import ItemBelief


class TrueMind(msgspec.Struct, frozen=True):
    """A simulated person's true belief over each item's location and true preference."""

    agent: Id
    beliefs: tuple[ItemBelief, ...]
    preference: Id
    """The item they want, or ``out``."""


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
