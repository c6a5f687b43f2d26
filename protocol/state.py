"""The world state an engine publishes on ``engine/state`` every tick."""

from __future__ import annotations

import enum
from typing import Annotated

import msgspec

from .geometry import Cell, Pose, Vec2
from .message import Id, Message, Seconds, Tick


class Activity(enum.Enum):
    """What an agent is doing this tick."""

    IDLE = "idle"
    MOVING = "moving"
    PLAYING = "playing"


class AgentState(msgspec.Struct, frozen=True):
    """A person's or robot's body.

    ``region`` is the region the agent is in; on a door cell, the last region it was in.
    """

    id: Id
    pose: Pose
    velocity: Vec2
    cell: Cell
    region: Id
    holding: Id | None = None
    """The item the agent carries, if any."""
    activity: Activity = Activity.IDLE


class ItemState(msgspec.Struct, frozen=True):
    """An item's body: resting at a ``location`` (spot id) or ``held_by`` an agent."""

    id: Id
    pose: Pose
    cell: Cell
    region: Id
    location: Id | None = None
    held_by: Id | None = None


class State(Message, frozen=True, kw_only=True, tag="state"):
    """The world at one tick: time, agents' and items' bodies, and who holds what."""

    episode: Annotated[int, msgspec.Meta(ge=0)]
    tick: Tick
    time: Seconds
    agents: tuple[AgentState, ...]
    items: tuple[ItemState, ...]
    done: bool = False
    """The scenario has ended (its scripts are over and the robot idle, or its time limit
    is reached). The engine still steps when asked."""
