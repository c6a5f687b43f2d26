"""Gateway frames: one world's protocol carried over a WebSocket, for clients without Zenoh.

A client (a Unity scene, any program with a WebSocket) talks to ``toyroom gateway`` in
text frames, one JSON object each, told apart by their ``op``. The first frame is
:class:`GatewayHello`; the gateway answers :class:`Welcome` (or :class:`FrameError` and
closes). After that the client publishes (:class:`Put`), subscribes (:class:`Subscribe`,
answered by :class:`Sample` frames), serves queryables (:class:`Serve`, answered by
:class:`Query` frames that the client answers with :class:`Reply`) and queries
(:class:`Get`, answered by one :class:`Replies` frame); :class:`Batch` carries several of
these in one message.

Keys are relative to the world, ``toyroom/<world>/``: ``engine/state``, ``robot/*/command``.
A payload is a protocol message as a JSON object, embedded as it is (never a string
holding JSON). Every malformed frame is answered with a :class:`FrameError` naming the
field at fault; the connection stays open.
"""

from __future__ import annotations

from typing import Annotated

import msgspec

from .version import PROTOCOL_VERSION

FRAMES_VERSION = "1"
"""Version of the frame format (independent of the protocol's message version)."""

Payload = Annotated[
    msgspec.Raw,
    msgspec.Meta(
        extra_json_schema={
            "type": "object",
            "description": "A protocol message (protocol/schema/<type>.json) as a JSON object.",
        }
    ),
]
"""A protocol message as a JSON object, carried byte for byte."""


MaybePayload = Annotated[
    msgspec.Raw,
    msgspec.Meta(
        extra_json_schema={
            "type": ["object", "null"],
            "description": "A protocol message as a JSON object, or null for none.",
        }
    ),
]
"""A payload or ``null`` (a query without one)."""

NONE = msgspec.Raw(b"null")
"""The ``null`` payload."""


class Frame(msgspec.Struct, frozen=True, kw_only=True, tag_field="op"):
    """Base of every frame: its ``op`` tag."""


class GatewayHello(Frame, frozen=True, kw_only=True, tag="hello"):
    """Client -> gateway, first: who the client is. The gateway declares the liveliness token
    ``toyroom/<world>/@alive/<role>/<name>`` for as long as the socket is open, so a dropped
    connection reads as a lost node within a second."""

    role: str
    """The node's role: ``engine`` for an engine."""
    name: str
    """The node's name, unique in the world (a key chunk: letters, digits, '_', '-')."""
    token: str | None = None
    """The gateway's secret when it was started with ``--token FILE``."""
    frames: str = FRAMES_VERSION
    """The frame format the client speaks."""
    client: str = ""
    """Free text naming the client program, for the gateway's log."""


class Welcome(Frame, frozen=True, kw_only=True, tag="welcome"):
    """Gateway -> client: the hello was accepted."""

    world: str
    """The world this gateway carries."""
    prefix: str
    """The Zenoh key prefix every frame key is relative to, ``toyroom/<world>``."""
    protocol: str = PROTOCOL_VERSION
    """The protocol version of the gateway's toyroom."""
    frames: str = FRAMES_VERSION
    gateway: str = ""
    """The gateway program and version."""


class Put(Frame, frozen=True, kw_only=True, tag="put"):
    """Client -> gateway: publish ``payload`` on ``key`` (no wildcards)."""

    key: str
    payload: Payload


class Subscribe(Frame, frozen=True, kw_only=True, tag="subscribe"):
    """Client -> gateway: send a :class:`Sample` for every message published on ``key``
    (wildcards ``*`` and ``**`` allowed) until :class:`Unsubscribe` with the same ``id``."""

    id: int
    """The client's number for this subscription (any integer, unique among its subscriptions)."""
    key: str


class Unsubscribe(Frame, frozen=True, kw_only=True, tag="unsubscribe"):
    """Client -> gateway: end subscription ``id``."""

    id: int


class Serve(Frame, frozen=True, kw_only=True, tag="serve"):
    """Client -> gateway: answer queries on ``key`` (e.g. ``engine/control``); each arrives as a
    :class:`Query` frame until :class:`Unserve` with the same ``id``."""

    id: int
    key: str


class Unserve(Frame, frozen=True, kw_only=True, tag="unserve"):
    """Client -> gateway: stop serving ``id``; its unanswered queries get an error reply."""

    id: int


class Reply(Frame, frozen=True, kw_only=True, tag="reply"):
    """Client -> gateway: the answer to query ``qid``. ``ok`` false sends ``payload`` (an
    ``error`` message) as an error reply, as a Zenoh engine's ``reply_err`` does."""

    qid: int
    payload: Payload
    ok: bool = True


class Get(Frame, frozen=True, kw_only=True, tag="get"):
    """Client -> gateway: query ``key`` and send back every answer in one :class:`Replies`."""

    id: int
    key: str
    payload: MaybePayload = msgspec.field(default_factory=lambda: NONE)
    timeout: float = 5.0
    """Seconds to wait for answers."""


class Batch(Frame, frozen=True, kw_only=True, tag="batch"):
    """Client -> gateway: several frames in one WebSocket message, acted on in order (an
    engine sends a tick's events, statuses, state and the step's reply as one batch: one
    message instead of four, and one wake-up of the gateway)."""

    frames: list[Put | Subscribe | Unsubscribe | Serve | Unserve | Reply | Get]


class Sample(Frame, frozen=True, kw_only=True, tag="sample"):
    """Gateway -> client: a message published on ``key``, for subscription ``sub``."""

    sub: int
    key: str
    payload: Payload


class Query(Frame, frozen=True, kw_only=True, tag="query"):
    """Gateway -> client: a query on ``key`` for served key ``serve``; answer it with a
    :class:`Reply` carrying the same ``qid`` (queries may be answered in any order, and the
    querier waits for the answer: a lock-step ``step`` is answered after the engine has run)."""

    serve: int
    qid: int
    key: str
    payload: MaybePayload = msgspec.field(default_factory=lambda: NONE)


class Answer(msgspec.Struct, frozen=True, kw_only=True):
    """One answer of a :class:`Get`."""

    key: str
    ok: bool
    payload: Payload


class Replies(Frame, frozen=True, kw_only=True, tag="replies"):
    """Gateway -> client: every answer to :class:`Get` ``id`` (empty: nobody answered in time)."""

    id: int
    replies: list[Answer]


class FrameError(Frame, frozen=True, kw_only=True, tag="error"):
    """Gateway -> client: a frame was refused; ``ref`` is its ``id`` or ``qid`` when it had one."""

    code: str
    """``bad_frame`` (not a frame, or a field is wrong), ``bad_payload`` (not a protocol message),
    ``bad_key``, ``unknown_id``, ``not_welcome`` (no hello yet), ``unauthorized`` or ``internal``."""
    message: str
    """What was wrong: the frame's op and field and what came instead."""
    ref: int | None = None


ClientFrame = GatewayHello | Put | Subscribe | Unsubscribe | Serve | Unserve | Reply | Get | Batch
"""Every frame a client sends."""

GatewayFrame = Welcome | Sample | Query | Replies | FrameError
"""Every frame the gateway sends."""

FRAME_TYPES: tuple[type[Frame], ...] = (
    GatewayHello,
    Welcome,
    Put,
    Subscribe,
    Unsubscribe,
    Serve,
    Unserve,
    Reply,
    Get,
    Batch,
    Sample,
    Query,
    Replies,
    FrameError,
)
"""All frame types, in the order the documentation lists them."""
