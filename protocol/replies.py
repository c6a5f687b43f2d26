"""Replies to queries: :class:`ControlReply` on success, :class:`ErrorReply` on failure.

An ``ErrorReply`` travels as a Zenoh *error* reply (``reply_err``) with the same encodings
as any message, so a client can tell a refused request from a malformed one.
"""

from __future__ import annotations

import enum
from typing import Annotated

import msgspec

from .events import Event
from .message import Message, Seconds, Tick
from .robot import CommandStatus
from .state import State


class ControlReply(Message, frozen=True, kw_only=True, tag="control_reply"):
    """The engine's clock after a control request was carried out."""

    episode: Annotated[int, msgspec.Meta(ge=0)]
    """Counts resets since the engine started; a state of an older episode is stale."""
    tick: Tick
    time: Seconds
    paused: bool = False
    state: State | None = None
    """The state after the request (after the last tick of a ``step``): the same message
    that was published on ``engine/state``, so a lock-step client needs no race with its
    subscription. Engines with the ``lockstep`` capability include it."""
    events: tuple[Event, ...] = ()
    """Every event the request produced (all ticks of a ``step``), in publication order:
    with ``state``, everything a lock-step client needs to follow the world exactly."""
    statuses: tuple[CommandStatus, ...] = ()
    """Every robot command status the request produced, in publication order (they are
    also published on ``robot/<id>/status``)."""


class ErrorCode(enum.Enum):
    """Why a request was refused."""

    BAD_REQUEST = "bad_request"
    """The request could not be decoded or is not valid for this key."""
    VERSION_MISMATCH = "version_mismatch"
    """The request's protocol major version differs from the engine's."""
    UNKNOWN_SCENARIO = "unknown_scenario"
    UNSUPPORTED = "unsupported"
    """The engine lacks the capability (e.g. ``step`` on a real-time-only engine)."""
    INTERNAL = "internal"
    """The engine failed while carrying out a valid request."""


class ErrorReply(Message, frozen=True, kw_only=True, tag="error"):
    """A refused query: a machine-readable ``code`` and a sentence saying what was wrong."""

    code: ErrorCode
    message: str
