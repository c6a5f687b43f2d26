"""The handshake: a client's :class:`Hello` and the engine's :class:`EngineInfo`.

A client (brain, viewer, recorder, conformance kit) queries ``engine/info`` with a
``Hello`` as payload; the engine answers with ``EngineInfo``, or with an ``error`` reply
when the client's major version differs from its own.
"""

from __future__ import annotations

import enum
from typing import Annotated

import msgspec

from .message import Id, Message
from .scene import Scene
from .vocabulary import described, known


class Capability(enum.StrEnum):
    """Optional engine features, declared by name in the handshake (an open vocabulary:
    a client ignores a capability it does not know).

    - ``lockstep``: the engine advances only on ``step`` requests (reproducible runs).
    - ``realtime``: the engine can free-run at a multiple of wall-clock time.
    - ``truth``: the engine publishes simulated people's true minds on ``engine/truth``.
    - ``robot``: the engine executes robot commands on ``robot/<id>/command``.
    """

    LOCKSTEP = "lockstep"
    REALTIME = "realtime"
    TRUTH = "truth"
    ROBOT = "robot"


CapabilityName = Annotated[str, described(Capability, "capability")]


class ClockMode(enum.Enum):
    """How the engine's clock runs right now."""

    LOCKSTEP = "lockstep"
    REALTIME = "realtime"


class Hello(Message, frozen=True, kw_only=True, tag="hello"):
    """Sent by a client as the payload of its ``engine/info`` query."""

    client: str
    """Client software name, e.g. ``"toyroom-brain 0.1.0"``."""
    role: str = "client"
    """What the client is: ``brain``, ``viewer``, ``recorder``, ``conform``..."""


class EngineInfo(Message, frozen=True, kw_only=True, tag="engine_info"):
    """The engine's answer to the handshake: who it is, what it can do, and the scene."""

    engine: str
    """Engine software name and version, e.g. ``"sim2d 0.1.0"`` or ``"MyUnityScene 2.3"``."""
    world: Id
    """The world name: the ``<world>`` in every key ``toyroom/<world>/...``."""
    scenario: str
    """The scenario loaded now (``""`` when the engine has no notion of scenarios)."""
    capabilities: tuple[CapabilityName, ...]
    """:class:`Capability` members when known, else the strings as sent."""
    clock: ClockMode
    tick_seconds: Annotated[float, msgspec.Meta(gt=0.0)]
    """Simulated seconds per tick."""
    episode: Annotated[int, msgspec.Meta(ge=0)] = 0
    """Counts resets since the engine started."""
    scene: Scene

    def __post_init__(self) -> None:
        msgspec.structs.force_setattr(
            self, "capabilities", tuple(known(Capability, c) for c in self.capabilities)
        )
