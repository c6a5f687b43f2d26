"""Requests to the engine's clock, sent as queries to ``engine/control``.

Each is answered with a :class:`~protocol.replies.ControlReply` once done (for ``step``,
after the last state of the step has been published), or with an ``error`` reply.
"""

from __future__ import annotations

from typing import Annotated

import msgspec

from .message import Message


class Reset(Message, frozen=True, kw_only=True, tag="reset"):
    """Start a new episode: load ``scenario`` (``None``: the current one) with ``seed``.

    The engine publishes the episode's first state (tick 0) before replying.
    """

    scenario: str | None = None
    seed: Annotated[int, msgspec.Meta(ge=0)] = 0


class Step(Message, frozen=True, kw_only=True, tag="step"):
    """Lock-step: advance exactly ``n`` ticks, publishing one state per tick, then reply."""

    n: Annotated[int, msgspec.Meta(ge=1, le=1_000_000)] = 1


class Pause(Message, frozen=True, kw_only=True, tag="pause"):
    """Stop a free-running (real-time) clock; the engine keeps answering queries."""


class Resume(Message, frozen=True, kw_only=True, tag="resume"):
    """Restart a paused real-time clock."""
