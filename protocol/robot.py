"""Robot commands (``robot/<id>/command``, brain -> engine) and their statuses
(``robot/<id>/status``, engine -> brain).

Each command carries an ``id`` chosen by the brain; the engine answers with statuses for
that id: ``accepted`` (or ``failed`` at once), then ``running``, then exactly one of
``succeeded``, ``failed`` (with a ``reason``) or ``cancelled``. The engine never decides
anything for the robot: it only carries out what it is told, or says why it cannot.
"""

from __future__ import annotations

import enum
import threading
from collections.abc import Mapping
from typing import Annotated, Any

import msgspec

from .geometry import Cell
from .message import Id, Message, Tick

EARSHOT_CELLS = 2
"""A person hears the robot (a ``say`` or an ``ask``) in the same region or within this many
cells (Manhattan, walls ignored): the protocol's earshot, every engine's."""


class Navigate(msgspec.Struct, frozen=True, tag_field="kind", tag="navigate"):
    """Drive to ``cell`` along walkable cells."""

    cell: Cell


class Pick(msgspec.Struct, frozen=True, tag_field="kind", tag="pick"):
    """Pick up ``item`` from the location the robot stands on (or next to)."""

    item: Id


class Place(msgspec.Struct, frozen=True, tag_field="kind", tag="place"):
    """Put the carried item down at ``location`` (the robot stands on or next to it)."""

    location: Id


class Give(msgspec.Struct, frozen=True, tag_field="kind", tag="give"):
    """Hand the carried item to ``person`` (within reach: same or neighbouring cell)."""

    person: Id


class SayTopic(enum.Enum):
    """What the robot tells a person about an item."""

    LOCATION = "location"
    """``item`` is at ``location``."""
    OCCUPIED = "occupied"
    """``item`` is held by ``holder``."""


class Told(msgspec.Struct, frozen=True):
    """One more item told of in the same ``say`` (from 1.6): ``item`` is at ``location``."""

    item: Id
    location: Id


class Say(msgspec.Struct, frozen=True, tag_field="kind", tag="say"):
    """Tell ``person`` where ``item`` is (``topic=location``) or who holds it (``occupied``).

    ``also`` (optional, from 1.6; ``topic=location`` only): more items told of in the same
    utterance ("the ball is in the kitchen, the skate in the garden"), each a :class:`Told`.
    A 1.5 engine ignores it and tells of ``item`` alone."""

    person: Id
    item: Id
    topic: SayTopic
    location: Id | None = None
    holder: Id | None = None
    also: tuple[Told, ...] = ()

    def __post_init__(self) -> None:
        if self.topic is SayTopic.LOCATION and self.location is None:
            raise ValueError("say with topic 'location' needs field 'location'")
        if self.topic is SayTopic.OCCUPIED and self.holder is None:
            raise ValueError("say with topic 'occupied' needs field 'holder'")
        if self.also and self.topic is not SayTopic.LOCATION:
            raise ValueError("say with field 'also' needs topic 'location'")
        items = [self.item, *(t.item for t in self.also)]
        if len(set(items)) < len(items):
            raise ValueError(f"say tells of an item twice: {items}")

    @property
    def told(self) -> tuple[Told, ...]:
        """Every item told of and where (``topic=location``): ``item`` first, then ``also``;
        empty for ``topic=occupied``."""
        if self.topic is not SayTopic.LOCATION or self.location is None:
            return ()
        return (Told(self.item, self.location), *self.also)


class Request(msgspec.Struct, frozen=True, tag_field="kind", tag="request"):
    """Ask ``person`` to hand over ``item``, offering ``offer`` in exchange (or nothing).

    Succeeds when the person answers (the answer comes as a ``reply`` event and in the
    status' ``answer``); fails when they cannot be asked: unknown, not holding ``item``, or
    out of reach of a hand-over (not on or next to the robot, 4-neighbour).
    """

    person: Id
    item: Id
    offer: Id | None = None


class Ask(msgspec.Struct, frozen=True, tag_field="kind", tag="ask"):
    """Ask ``person`` what they are looking for (``item`` null: an open question) or whether
    they want ``item`` (a yes/no question); from 1.6.

    Within earshot (as ``say``). Succeeds when the person answers: an ``answer`` event
    (``actor`` the person, ``target`` the robot) carries it, ``item`` the item the answer is
    about and ``answer`` whether they want it (an open question: the item they want and true,
    or ``item`` null and false: nothing); the status' ``answer`` is the same yes or no. Fails
    when they cannot be asked (unknown, out of earshot) or do not answer (``no answer: ...``).
    """

    person: Id
    item: Id | None = None


class Cancel(msgspec.Struct, frozen=True, tag_field="kind", tag="cancel"):
    """Cancel command ``command``, running or still queued; it ends with status ``cancelled``."""

    command: Id


Action = Navigate | Pick | Place | Give | Say | Request | Ask | Cancel
"""Every command kind the robot body executes (the known set of an open vocabulary: a
command of another kind decodes to an :class:`UnknownAction`)."""
COMMAND_KINDS: tuple[str, ...] = tuple(str(t.__struct_config__.tag) for t in Action.__args__)
"""The known command kinds, in the order of :data:`Action`."""


class UnknownAction(msgspec.Struct, frozen=True):
    """A command of a kind this side does not know (from a peer of a newer minor version):
    its fields kept as sent, so it re-encodes unchanged. An engine fails it with a reason
    naming the kind (:func:`unknown_action` builds one)."""

    @property
    def kind(self) -> str:
        """The command kind as sent."""
        return str(type(self).__struct_config__.tag)

    def fields(self) -> dict[str, Any]:
        """The command's fields as sent, less ``kind``."""
        return {name: getattr(self, name) for name in self.__struct_fields__}


_UNKNOWN: dict[tuple[str, tuple[str, ...]], type[UnknownAction]] = {}
_UNKNOWN_LOCK = threading.Lock()


def unknown_action(kind: str, fields: Mapping[str, Any]) -> UnknownAction:
    """An :class:`UnknownAction` of ``kind`` holding ``fields`` (a class per kind and field
    names, made once)."""
    names = tuple(sorted(k for k in fields if k != "kind"))
    with _UNKNOWN_LOCK:
        if (kind, names) not in _UNKNOWN:
            _UNKNOWN[(kind, names)] = msgspec.defstruct(  # type: ignore[assignment]
                "UnknownAction",
                [(name, Any, None) for name in names],
                bases=(UnknownAction,),
                tag_field="kind",
                tag=kind,
                frozen=True,
            )
        cls = _UNKNOWN[(kind, names)]
    return cls(**{name: fields[name] for name in names})


class RobotCommand(Message, frozen=True, kw_only=True, tag="robot_command"):
    """A command for robot ``robot``; ``id`` is echoed in every status about it."""

    id: Id
    robot: Id
    action: Action
    """One of the known kinds, or an :class:`UnknownAction` when decoded from a peer that
    sent another kind."""


class CommandState(enum.Enum):
    """The life of a command: accepted -> running -> succeeded | failed | cancelled."""

    ACCEPTED = "accepted"
    RUNNING = "running"
    SUCCEEDED = "succeeded"
    FAILED = "failed"
    CANCELLED = "cancelled"

    @property
    def final(self) -> bool:
        """Whether no further status follows this one."""
        return self in (CommandState.SUCCEEDED, CommandState.FAILED, CommandState.CANCELLED)


class CommandStatus(Message, frozen=True, kw_only=True, tag="command_status"):
    """Where command ``command`` of robot ``robot`` stands, at engine tick ``tick``.

    ``reason`` says why on ``failed`` (e.g. ``"unreachable: no path to (3,4)"``,
    ``"item not there: 'ball' is at S1"``, ``"item held by A2"``, ``"unknown id 'A9'"``).
    ``answer`` is the person's yes/no for a finished ``request``.
    """

    command: Id
    robot: Id
    state: CommandState
    tick: Tick
    reason: str = ""
    answer: bool | None = None


class Heartbeat(Message, frozen=True, kw_only=True, tag="heartbeat"):
    """The brain is alive and still driving robot ``robot`` (on ``robot/<id>/heartbeat``).

    A real-time engine stops the robot, failing its commands, when neither a heartbeat nor a
    command has come for its heartbeat timeout (sim2d: 1 s); brains send one every 0.25 s.
    """

    robot: Id
    seq: Annotated[int, msgspec.Meta(ge=0)] = 0
