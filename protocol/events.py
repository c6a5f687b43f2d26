"""Discrete events an engine publishes on ``engine/events``, one message per event."""

from __future__ import annotations

import enum
from typing import Annotated

import msgspec

from .message import Id, Message, Seconds, Tick
from .vocabulary import described, known


class EventKind(enum.StrEnum):
    """What happened (an open vocabulary: a receiver ignores a kind it does not know, and
    a recorder keeps it). Fields used by each kind are listed with it.

    - ``enter`` / ``leave``: ``actor`` entered / left region ``location``.
    - ``take``: ``actor`` took ``item`` from ``location``.
    - ``drop``: ``actor`` put ``item`` down at ``location``.
    - ``play`` / ``stop``: ``actor`` started / stopped playing with ``item`` at ``location``.
    - ``use``: ``actor`` used ``item``, resting at the ``use`` location ``location``, in place.
    - ``give``: ``actor`` handed ``item`` to ``target``.
    - ``say``: ``actor`` told ``target`` something about ``item`` (``location`` where it is,
      or ``detail`` ``"occupied by <id>"``).
    - ``request``: ``actor`` asked ``target`` for ``item``, offering ``offer`` (or nothing).
    - ``reply``: ``actor`` answered ``target``'s request: ``answer`` true (yes) or false.
    - ``ask`` (from 1.6): ``actor`` asked ``target`` what they want (``item`` null) or
      whether they want ``item``.
    - ``answer`` (from 1.6): ``actor`` answered ``target``'s ``ask``: they want ``item``
      (``answer`` true) or not (false); ``item`` null and ``answer`` false: nothing.
    - ``waypoint``: a scripted ``actor`` completed the scenario step ``label``.
    """

    ENTER = "enter"
    LEAVE = "leave"
    TAKE = "take"
    DROP = "drop"
    PLAY = "play"
    STOP = "stop"
    USE = "use"
    GIVE = "give"
    SAY = "say"
    REQUEST = "request"
    REPLY = "reply"
    ASK = "ask"
    ANSWER = "answer"
    WAYPOINT = "waypoint"


EventKindName = Annotated[str, described(EventKind, "event kind")]


class Event(Message, frozen=True, kw_only=True, tag="event"):
    """One discrete event, stamped with the tick at which it happened."""

    episode: Annotated[int, msgspec.Meta(ge=0)]
    tick: Tick
    time: Seconds
    kind: EventKindName
    """An :class:`EventKind` member when known, else the string as sent."""
    actor: Id
    item: Id | None = None
    location: Id | None = None
    target: Id | None = None
    offer: Id | None = None
    answer: bool | None = None
    label: str | None = None
    detail: str = ""

    def __post_init__(self) -> None:
        msgspec.structs.force_setattr(self, "kind", known(EventKind, self.kind))
