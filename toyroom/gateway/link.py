"""One client of the gateway: its socket, and what it declared on Zenoh for it.

A :class:`ClientLink` reads the client's frames on the socket's handler thread and acts on
them (puts, declarations, replies); Zenoh's threads hand it samples and queries, which it
queues for the client's own writer thread (:mod:`.outbox`: a client too slow to read is
dropped, and holds up nobody else); it holds each query until the client replies
(:mod:`.pending`). Everything it declared, its liveliness token first, is undeclared as soon
as the socket closes, and its unanswered queries are let go, so the querier learns at once
that the engine has gone; a client dropped for a frame above the gateway's limit (1009) has
them refused with a line that says so (:func:`too_big_message`).
"""

from __future__ import annotations

import hmac
import logging
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import msgspec
import zenoh
from websockets.exceptions import ConnectionClosed
from websockets.sync.server import ServerConnection

from bridge.pubsub import FOREVER
from protocol import Encoding, ErrorCode, ErrorReply, ProtocolError, check_name, encode
from protocol.frames import (
    FRAMES_VERSION,
    NONE,
    Answer,
    Batch,
    ClientFrame,
    FrameError,
    GatewayHello,
    Get,
    Put,
    Query,
    Replies,
    Reply,
    Sample,
    Serve,
    Subscribe,
    Unserve,
    Unsubscribe,
    Welcome,
)
from protocol.limits import MAX_FRAME_BYTES

from .checks import Refusal, checked_payload, read_frame, to_json
from .keepalive import Keepalive
from .outbox import Outbox, QueueLimits
from .pending import PendingQueries

log = logging.getLogger("toyroom.gateway")

_encoder = msgspec.json.Encoder()
_JSON = zenoh.Encoding(Encoding.JSON.value)


@dataclass(frozen=True)
class LinkSettings:
    """What every link of one gateway shares."""

    world: str
    secret: str | None
    gateway: str
    """The gateway's program and version, for :class:`Welcome`."""
    queue: QueueLimits = QueueLimits()
    """How much a client may have waiting to be sent before it is dropped (:mod:`.outbox`)."""
    ping: float = 0.5
    """Seconds between pings; a client that answers none and sends nothing for this long after
    one is dropped (:mod:`.keepalive`)."""

    @property
    def prefix(self) -> str:
        return f"toyroom/{self.world}"


TOO_BIG = 1009
"""The close code of a client that sent a frame above the gateway's limit (``websockets``' own)."""
UNAUTHORIZED = 4001
"""The close code of a client whose hello has the wrong token (after an ``unauthorized`` error)."""


def too_big_message(client: str, reason: str) -> str:
    """What the querier of a client dropped for a frame too big is told (one line)."""
    return (
        f"the gateway dropped the client serving this key ({client}): it sent a frame above the gateway's "
        f"limit of {MAX_FRAME_BYTES:,} bytes ({reason}); a scene must fit that limit (docs/usage.md, Limits)"
    )


class ClientLink:
    """The gateway's side of one WebSocket client (see the module docstring)."""

    def __init__(self, socket: ServerConnection, session: zenoh.Session, settings: LinkSettings) -> None:
        self.socket = socket
        self.session = session
        self.settings = settings
        address = socket.remote_address
        self.peer = f"{address[0]}:{address[1]}" if address else "?"
        self.hello: GatewayHello | None = None
        self._token: Any = None
        self._subscribers: dict[int, Any] = {}
        self._queryables: dict[int, Any] = {}
        self._publishers: dict[str, zenoh.Publisher] = {}
        self._pending = PendingQueries()
        self._lock = threading.Lock()
        self._outbox = Outbox(socket, lambda: self.name, settings.queue, on_drop=self.withdraw)
        self.heard = time.monotonic()
        """When the last frame came from the client (``time.monotonic``)."""
        self._keepalive = Keepalive(self._outbox, settings.ping, lambda: self.heard)
        self.closed = False

    # ----- sending -------------------------------------------------------------------------

    def send(self, frame: msgspec.Struct) -> None:
        """Queue one frame for the client's writer (never waits; :mod:`.outbox`); once the
        link is closing, the frame is discarded."""
        self._outbox.put(_encoder.encode(frame))

    def refuse(self, code: str, message: str, ref: int | None = None) -> None:
        log.warning("client %s: %s: %s", self.name, code, message)
        self.send(FrameError(code=code, message=message, ref=ref))

    @property
    def name(self) -> str:
        return f"{self.hello.role}/{self.hello.name}" if self.hello else self.peer

    # ----- the read loop -------------------------------------------------------------------

    def run(self) -> None:
        """Read and act on frames until the socket closes; then undeclare everything."""
        too_big = None
        try:
            for data in self.socket:
                self.handle(data if isinstance(data, bytes) else data.encode())
        except ConnectionClosed as closed:
            too_big = self._closed_by_gateway(closed)
        finally:
            self.close(too_big)

    def _closed_by_gateway(self, closed: ConnectionClosed) -> str | None:
        """Log, in one line, a close the gateway made for a fault (unless it was logged as it
        was made); the reason of a close for a frame too big (1009), else ``None``."""
        sent = closed.sent
        if (
            sent is None
            or closed.rcvd_then_sent
            or sent.code in (1000, 1001, UNAUTHORIZED)
            or self._outbox.dropped
        ):
            return None
        log.warning("client %s dropped: %s (%d)", self.name, sent.reason, sent.code)
        return sent.reason if sent.code == TOO_BIG else None

    def handle(self, data: bytes) -> None:
        """Act on one frame; every failure becomes an error frame, never an exception."""
        self.heard = time.monotonic()
        try:
            frame = read_frame(data)
        except Refusal as err:
            self.refuse(err.code, err.message)
            return
        try:
            self.dispatch(frame)
        except Refusal as err:
            self.refuse(err.code, err.message, err.ref)
        except Exception as err:
            log.exception("client %s: a '%s' frame failed", self.name, type(frame).__name__)
            self.refuse("internal", f"{type(err).__name__}: {err}")

    def dispatch(self, frame: ClientFrame) -> None:
        if isinstance(frame, GatewayHello):
            self.welcome(frame)
            return
        if self.hello is None:
            raise Refusal("not_welcome", "the first frame must be 'hello' (see protocol/README.md)")
        handlers: dict[type, Callable[[Any], None]] = {
            Put: self.put,
            Subscribe: self.subscribe,
            Unsubscribe: self.unsubscribe,
            Serve: self.serve,
            Unserve: self.unserve,
            Reply: self.reply,
            Get: self.get,
        }
        if isinstance(frame, Batch):
            for inner in frame.frames:  # each refused on its own, the rest still acted on
                try:
                    handlers[type(inner)](inner)
                except Refusal as err:
                    self.refuse(err.code, err.message, err.ref)
            return
        handlers[type(frame)](frame)

    # ----- frames --------------------------------------------------------------------------

    def welcome(self, hello: GatewayHello) -> None:
        if self.hello is not None:
            raise Refusal("bad_frame", "'hello' was already accepted on this connection")
        secret = self.settings.secret
        if secret is not None and not hmac.compare_digest((hello.token or "").encode(), secret.encode()):
            self.refuse("unauthorized", "the hello's token does not match the gateway's --token file")
            self._outbox.finish(UNAUTHORIZED, "unauthorized")  # after the error frame
            return
        if hello.frames.split(".")[0] != FRAMES_VERSION:
            raise Refusal("bad_frame", f"this gateway speaks frames {FRAMES_VERSION}, got {hello.frames!r}")
        try:
            role, name = check_name(hello.role, "role"), check_name(hello.name, "node")
        except ProtocolError as err:
            raise Refusal("bad_frame", f"hello: {err}") from None
        token = self.session.liveliness().declare_token(f"{self.settings.prefix}/@alive/{role}/{name}")
        with self._lock:
            self._token = token
        if self._outbox.dropped is not None:  # dropped meanwhile (not before a welcome, in practice)
            self.withdraw()
        self.hello = hello
        log.info("client %s (%s) joined from %s", self.name, hello.client or "?", self.peer)
        self.send(
            Welcome(world=self.settings.world, prefix=self.settings.prefix, gateway=self.settings.gateway)
        )

    def full_key(self, key: str, ref: int | None, wildcards: bool) -> str:
        """``toyroom/<world>/key``, checked."""
        if not key or key.startswith("/") or key.endswith("/") or "//" in key:
            raise Refusal("bad_key", f"keys are relative to the world, like 'engine/state'; got {key!r}", ref)
        if key.split("/")[0] == "@alive":
            raise Refusal("bad_key", "liveliness keys are the gateway's own (send 'hello')", ref)
        if not wildcards and "*" in key:
            raise Refusal("bad_key", f"a put or get key has no wildcards, got {key!r}", ref)
        full = f"{self.settings.prefix}/{key}"
        try:
            zenoh.KeyExpr(full)
        except Exception as err:
            raise Refusal("bad_key", f"not a key expression: {key!r} ({err})", ref) from None
        return full

    def relative(self, key: str) -> str:
        return key[len(self.settings.prefix) + 1 :]

    def put(self, frame: Put) -> None:
        key = self.full_key(frame.key, None, wildcards=False)
        data = checked_payload(frame.payload, f"put on '{frame.key}'", None)
        publisher = self._publishers.get(key)
        if publisher is None:
            publisher = self._publishers[key] = self.session.declare_publisher(
                key, encoding=_JSON, congestion_control=zenoh.CongestionControl.BLOCK
            )
        publisher.put(data)

    def subscribe(self, frame: Subscribe) -> None:
        key = self.full_key(frame.key, frame.id, wildcards=True)
        if frame.id in self._subscribers:
            raise Refusal("bad_frame", f"subscription {frame.id} exists (unsubscribe it first)", frame.id)
        sub = frame.id

        def on_sample(sample: zenoh.Sample) -> None:
            try:
                payload = to_json(sample.payload.to_bytes(), str(sample.encoding))
            except (ValueError, msgspec.DecodeError) as err:
                log.warning("not forwarded to %s: a payload on %s that is not JSON (%s)", self.name, key, err)
                return
            relative = self.relative(str(sample.key_expr))
            self.send(Sample(sub=sub, key=relative, payload=msgspec.Raw(payload)))

        self._subscribers[frame.id] = self.session.declare_subscriber(key, on_sample)

    def unsubscribe(self, frame: Unsubscribe) -> None:
        subscriber = self._subscribers.pop(frame.id, None)
        if subscriber is None:
            raise Refusal("unknown_id", f"no subscription {frame.id}", frame.id)
        subscriber.undeclare()

    def serve(self, frame: Serve) -> None:
        key = self.full_key(frame.key, frame.id, wildcards=True)
        if frame.id in self._queryables:
            raise Refusal("bad_frame", f"served key {frame.id} exists (unserve it first)", frame.id)
        serve = frame.id

        def on_query(query: zenoh.Query) -> None:
            self.forward(query, serve)

        self._queryables[frame.id] = self.session.declare_queryable(key, on_query)

    def forward(self, query: zenoh.Query, serve: int) -> None:
        """Hand a query to the client and keep it until the client's :class:`Reply`."""
        mime = str(query.encoding) if query.encoding is not None else None
        encoding = Encoding.from_mime(mime)
        payload = NONE
        if query.payload is not None and len(raw := query.payload.to_bytes()) > 0:
            try:
                payload = msgspec.Raw(to_json(raw, mime))
            except (ValueError, msgspec.DecodeError) as err:
                refusal = ErrorReply(code=ErrorCode.BAD_REQUEST, message=f"not JSON or MessagePack: {err}")
                query.reply_err(encode(refusal, encoding), encoding=zenoh.Encoding(encoding.value))
                return
        qid = self._pending.hold(query, encoding, serve)
        self.send(Query(serve=serve, qid=qid, key=self.relative(str(query.key_expr)), payload=payload))

    def reply(self, frame: Reply) -> None:
        pending = self._pending.take(frame.qid)
        if pending is None:
            raise Refusal("unknown_id", f"no unanswered query {frame.qid}", frame.qid)
        query, encoding = pending
        data = checked_payload(frame.payload, f"reply to query {frame.qid}", frame.qid)
        if encoding is Encoding.MSGPACK:
            data = msgspec.msgpack.encode(msgspec.json.decode(data))
        if frame.ok:
            query.reply(query.key_expr, data, encoding=zenoh.Encoding(encoding.value))
        else:
            query.reply_err(data, encoding=zenoh.Encoding(encoding.value))

    def unserve(self, frame: Unserve) -> None:
        queryable = self._queryables.pop(frame.id, None)
        if queryable is None:
            raise Refusal("unknown_id", f"no served key {frame.id}", frame.id)
        queryable.undeclare()
        self._pending.release_served(frame.id)

    def get(self, frame: Get) -> None:
        key = self.full_key(frame.key, frame.id, wildcards=True)
        data = (
            None
            if bytes(frame.payload) == b"null"
            else checked_payload(frame.payload, f"get {frame.id}", frame.id)
        )
        if not 0 < frame.timeout <= 3600:
            raise Refusal("bad_frame", f"get: timeout must be in (0, 3600] s, got {frame.timeout}", frame.id)
        threading.Thread(target=self._get, args=(frame, key, data), daemon=True).start()

    def _get(self, frame: Get, key: str, data: bytes | None) -> None:
        kwargs: dict[str, Any] = {"timeout": min(frame.timeout, FOREVER)}
        if data is not None:
            kwargs.update(payload=data, encoding=_JSON)
        answers = []
        for reply in self.session.get(key, **kwargs):
            sample, ok = (reply.ok, True) if reply.ok is not None else (reply.err, False)
            try:
                payload = to_json(sample.payload.to_bytes(), str(sample.encoding))
            except (ValueError, msgspec.DecodeError):
                continue  # Zenoh's own error text (a timeout): nobody answered
            answer_key = self.relative(str(sample.key_expr)) if ok else frame.key
            answers.append(Answer(key=answer_key, ok=ok, payload=msgspec.Raw(payload)))
        self.send(Replies(id=frame.id, replies=answers))

    # ----- closing -------------------------------------------------------------------------

    def withdraw(self) -> None:
        """Undeclare the client's liveliness token, at once (from any thread; safe twice): it
        was dropped, or its socket closed."""
        with self._lock:
            token, self._token = self._token, None
        if token is not None:
            try:
                token.undeclare()
            except Exception:
                pass

    def close(self, too_big: str | None = None) -> None:
        """Undeclare everything of this client, its liveliness token first, and let go of its
        held queries (``too_big``: the reason of its 1009 close, and the queries are refused
        saying so); safe twice."""
        if self.closed:
            return
        self.closed = True
        self._keepalive.stop()
        self._outbox.finish()
        self.withdraw()
        if too_big is None:
            self._pending.release_all()
        else:
            self._pending.refuse_all(too_big_message(self.name, too_big))
        for entity in [*self._subscribers.values(), *self._queryables.values()]:
            try:
                if entity is not None:
                    entity.undeclare()
            except Exception:
                pass
        for publisher in self._publishers.values():
            try:
                publisher.undeclare()
            except Exception:
                pass
        self._subscribers.clear()
        self._queryables.clear()
        self._publishers.clear()
        if self.hello is not None:
            log.info("client %s left", self.name)
