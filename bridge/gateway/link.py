"""One client of the gateway: its socket, and what it declared on Zenoh for it.

A :class:`ClientLink` reads the client's frames on the socket's handler thread and acts on
them (puts, declarations, replies); Zenoh's threads hand it samples and queries, which it
sends at once (a WebSocket send is thread-safe); it holds each query until the client
replies (:mod:`.pending`). Everything it declared, its liveliness token included, is
undeclared when the socket closes, and its unanswered queries are answered with an error,
so the querier learns at once that the engine has gone.
"""

from __future__ import annotations

import hmac
import logging
import threading
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import msgspec
import zenoh
from websockets.exceptions import ConnectionClosed
from websockets.sync.server import ServerConnection

from protocol import Encoding, ErrorCode, ErrorReply, ProtocolError, check_name, decode, encode
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

from ..pubsub import FOREVER
from .pending import PendingQueries

log = logging.getLogger("toyroom.gateway")

_frames = msgspec.json.Decoder(ClientFrame)
_encoder = msgspec.json.Encoder()
_JSON = zenoh.Encoding(Encoding.JSON.value)


@dataclass(frozen=True)
class LinkSettings:
    """What every link of one gateway shares."""

    world: str
    secret: str | None
    gateway: str
    """The gateway's program and version, for :class:`Welcome`."""

    @property
    def prefix(self) -> str:
        return f"toyroom/{self.world}"


class Refusal(Exception):
    """A frame is refused: becomes a :class:`FrameError` to the client."""

    def __init__(self, code: str, message: str, ref: int | None = None) -> None:
        super().__init__(message)
        self.code, self.message, self.ref = code, message, ref


def to_json(payload: bytes, mime: str | None) -> bytes:
    """A Zenoh payload as JSON bytes fit to embed in a frame (MessagePack is transcoded).

    Raises:
        ValueError: the payload is neither valid JSON nor valid MessagePack.
    """
    if Encoding.from_mime(mime) is Encoding.MSGPACK:
        return _encoder.encode(msgspec.msgpack.decode(payload))
    msgspec.json.decode(payload)  # must be one JSON value, or the frame would break
    return payload


TOO_DEEP = "nested too deeply to decode"
"""What a frame or payload nested too deeply to decode is told (msgspec's depth limit)."""


def checked_payload(raw: msgspec.Raw, where: str, ref: int | None) -> bytes:
    """A frame's payload after checking that it is a protocol message (any minor version)."""
    data = bytes(raw)
    try:
        decode(data, None, Encoding.JSON)
    except ProtocolError as err:
        raise Refusal("bad_payload", f"{where}: {err}", ref) from None
    except RecursionError:  # nested deeper than the decoder goes: not a message
        raise Refusal("bad_payload", f"{where}: {TOO_DEEP}", ref) from None
    return data


def read_frame(data: bytes) -> ClientFrame:
    """One client frame, decoded.

    Raises:
        Refusal: ``bad_frame`` naming what is wrong: not JSON, not a frame, a field of the
            wrong type, or nested too deeply to decode (which raises ``RecursionError`` in the
            decoder; caught here so that such a frame is refused like any other).
    """
    try:
        return _frames.decode(data)
    except msgspec.DecodeError as err:
        raise Refusal("bad_frame", f"not a gateway frame ({err}): {data[:120]!r}") from None
    except RecursionError:
        raise Refusal("bad_frame", f"not a gateway frame ({TOO_DEEP}): {data[:40]!r}...") from None


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
        self.closed = False

    # ----- sending -------------------------------------------------------------------------

    def send(self, frame: msgspec.Struct) -> None:
        """Send one frame; a closed socket is not an error (the link is closing)."""
        try:
            self.socket.send(_encoder.encode(frame), text=True)
        except ConnectionClosed:
            pass

    def refuse(self, code: str, message: str, ref: int | None = None) -> None:
        log.warning("client %s: %s: %s", self.name, code, message)
        self.send(FrameError(code=code, message=message, ref=ref))

    @property
    def name(self) -> str:
        return f"{self.hello.role}/{self.hello.name}" if self.hello else self.peer

    # ----- the read loop -------------------------------------------------------------------

    def run(self) -> None:
        """Read and act on frames until the socket closes; then undeclare everything."""
        try:
            for data in self.socket:
                self.handle(data if isinstance(data, bytes) else data.encode())
        except ConnectionClosed:
            pass
        finally:
            self.close()

    def handle(self, data: bytes) -> None:
        """Act on one frame; every failure becomes an error frame, never an exception."""
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
            self.socket.close(code=4001, reason="unauthorized")
            return
        if hello.frames.split(".")[0] != FRAMES_VERSION:
            raise Refusal("bad_frame", f"this gateway speaks frames {FRAMES_VERSION}, got {hello.frames!r}")
        try:
            role, name = check_name(hello.role, "role"), check_name(hello.name, "node")
        except ProtocolError as err:
            raise Refusal("bad_frame", f"hello: {err}") from None
        self._token = self.session.liveliness().declare_token(f"{self.settings.prefix}/@alive/{role}/{name}")
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

    def close(self) -> None:
        """Undeclare everything of this client and refuse its held queries; safe twice."""
        if self.closed:
            return
        self.closed = True
        self._pending.release_all()
        for entity in [self._token, *self._subscribers.values(), *self._queryables.values()]:
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
