"""What the brain node holds for the engine it follows (:class:`Link`), the signal that it
was asked to stop while waiting for one (:class:`Stopped`), and what a run declares
(:class:`Closable`)."""

from __future__ import annotations

import queue
from dataclasses import dataclass, field
from typing import Protocol

from bridge import Publisher
from protocol import CommandStatus, EngineInfo, Message

from .outputs.results import MindCache
from .outputs.shadows import ShadowMinds
from .realtime import Heartbeats
from .robot.controller import RobotBrain
from .tracking.tracker import MindTracker


class Closable(Protocol):
    """What a run subscribes to or declares, withdrawn when it ends."""

    def close(self) -> None: ...


class Stopped(Exception):
    """The node was asked to stop (:attr:`brain.node.BrainNode.stopping`) while waiting for its engine."""


@dataclass
class Link:
    """What the brain holds for the engine it follows."""

    info: EngineInfo
    tracker: MindTracker
    shadow: ShadowMinds | None
    robot: RobotBrain | None
    inbox: queue.Queue[CommandStatus] = field(default_factory=queue.Queue)
    """The robot's command statuses, as they arrive."""
    commands: Publisher[Message] | None = None
    heartbeats: Heartbeats | None = None
    """Real-time engines only."""
    minds: MindCache = field(default_factory=dict)
    """The ``mind`` message's parts kept between ticks (:func:`mind_message`)."""
