"""The grid engine's two ways onto the wire, behind one small interface:

- :class:`ZenohTransport`: a Zenoh peer on loopback, as protocol/README.md describes;
- :class:`GatewayTransport`: JSON frames over a WebSocket to ``toyroom gateway``, as
  protocol/README.md's "Engines without Zenoh" describes (no Zenoh in this process at all).

Both hand the engine parsed messages (dicts; ``{"type": None}`` for a payload that is not
one) and take dicts to send. Keys are relative to the world: ``engine/state``.
"""

from __future__ import annotations

import json
import sys
import threading
import zlib
from collections.abc import Callable
from typing import Any, Protocol

import msgspec

MSGPACK = "application/msgpack"
JSON_MIME = "application/json"
MALFORMED: dict[str, Any] = {"type": None}


def load(payload: bytes, mime: str) -> Any:
    """A payload as Python values: MessagePack when the encoding says so, else JSON."""
    if mime.split(";")[0].strip() == MSGPACK:
        return msgspec.msgpack.decode(payload)
    return json.loads(payload)


def parsed(payload: bytes, mime: str) -> dict[str, Any]:
    """A payload as a message dict, or :data:`MALFORMED`."""
    try:
        message = load(payload, mime)
    except (ValueError, msgspec.DecodeError):
        return MALFORMED
    return message if isinstance(message, dict) else MALFORMED


class Request(Protocol):
    """A query to answer: its message (``None``: no payload) and its encoding."""

    message: dict[str, Any] | None
    mime: str

    def reply(self, message: dict[str, Any], mime: str) -> None: ...

    def reply_err(self, message: dict[str, Any]) -> None: ...


Handler = Callable[[Request], None]
Listener = Callable[[dict[str, Any], str], None]
"""Called with a received message and its key (relative to the world)."""


# ----- Zenoh -------------------------------------------------------------------------------


def world_port(world: str) -> int:
    """As protocol/README.md says: 17000 + crc32(world) % 10000."""
    return 17000 + zlib.crc32(world.encode()) % 10000


class ZenohRequest:
    def __init__(self, query: Any) -> None:
        self.query = query
        self.mime = str(query.encoding) if query.encoding is not None else JSON_MIME
        self.message = None if query.payload is None else parsed(query.payload.to_bytes(), self.mime)

    def reply(self, message: dict[str, Any], mime: str) -> None:
        import zenoh

        if mime.split(";")[0].strip() == MSGPACK:
            payload, encoding = msgspec.msgpack.encode(message), zenoh.Encoding(MSGPACK)
        else:
            payload, encoding = json.dumps(message).encode(), zenoh.Encoding(JSON_MIME)
        self.query.reply(self.query.key_expr, payload, encoding=encoding)

    def reply_err(self, message: dict[str, Any]) -> None:
        import zenoh

        self.query.reply_err(json.dumps(message).encode(), encoding=zenoh.Encoding(JSON_MIME))


class ZenohTransport:
    """A loopback Zenoh peer, multicast off; listens on the world port when it is free."""

    def __init__(self, world: str) -> None:
        import zenoh

        self.prefix = f"toyroom/{world}"
        self._entities: list[Any] = []
        endpoint = f"tcp/127.0.0.1:{world_port(world)}"
        for listen in (endpoint, "tcp/127.0.0.1:0"):
            config = zenoh.Config()
            config.insert_json5("mode", '"peer"')
            config.insert_json5("scouting/multicast/enabled", "false")
            config.insert_json5("listen/endpoints", json.dumps([listen]))
            config.insert_json5("connect/endpoints", json.dumps([endpoint]))
            config.insert_json5("transport/link/tx/lease", "800")
            try:
                self.session = zenoh.open(config)
                break
            except zenoh.ZError:
                continue
        else:
            raise SystemExit(f"grid engine: cannot open a Zenoh session for world '{world}'")
        self._publishers: dict[str, Any] = {}

    def publish(self, key: str, message: dict[str, Any]) -> None:
        import zenoh

        publisher = self._publishers.get(key)
        if publisher is None:
            publisher = self._publishers[key] = self.session.declare_publisher(
                f"{self.prefix}/{key}", encoding=zenoh.Encoding(JSON_MIME)
            )
        publisher.put(json.dumps(message).encode())

    def serve(self, key: str, handler: Handler) -> None:
        self._entities.append(
            self.session.declare_queryable(f"{self.prefix}/{key}", lambda q: handler(ZenohRequest(q)))
        )

    def subscribe(self, key: str, listener: Listener) -> None:
        def on_sample(sample: Any) -> None:
            mime = str(sample.encoding) if sample.encoding is not None else JSON_MIME
            listener(parsed(sample.payload.to_bytes(), mime), str(sample.key_expr)[len(self.prefix) + 1 :])

        self._entities.append(self.session.declare_subscriber(f"{self.prefix}/{key}", on_sample))

    def announce(self, role: str, name: str) -> None:
        """Declare the liveliness token ``@alive/<role>/<name>``."""
        self._entities.append(self.session.liveliness().declare_token(f"{self.prefix}/@alive/{role}/{name}"))

    def close(self) -> None:
        for entity in self._entities:
            entity.undeclare()
        self.session.close()


# ----- the gateway ---------------------------------------------------------------------------


class GatewayRequest:
    def __init__(self, transport: GatewayTransport, frame: dict[str, Any]) -> None:
        self.transport = transport
        self.qid = frame["qid"]
        self.mime = JSON_MIME  # the gateway turns the answer into the querier's encoding
        payload = frame.get("payload")
        self.message = None if payload is None else payload if isinstance(payload, dict) else MALFORMED

    def reply(self, message: dict[str, Any], mime: str) -> None:
        self.transport.send({"op": "reply", "qid": self.qid, "ok": True, "payload": message})

    def reply_err(self, message: dict[str, Any]) -> None:
        self.transport.send({"op": "reply", "qid": self.qid, "ok": False, "payload": message})


class GatewayTransport:
    """JSON frames over a WebSocket to ``toyroom gateway`` (which holds the liveliness token
    for as long as the socket is open)."""

    def __init__(self, url: str, role: str, name: str, token: str | None = None) -> None:
        import time
        from contextlib import ExitStack

        from websockets.sync.client import connect

        self._stack = ExitStack()
        for attempt in range(100):  # the gateway may still be starting: retry for 10 s
            try:
                self.socket = self._stack.enter_context(
                    connect(url, proxy=None, compression=None, max_size=16 * 1024 * 1024)
                )
                break
            except ConnectionRefusedError:
                if attempt == 99:
                    raise SystemExit(f"grid engine: no gateway answers at {url}") from None
                time.sleep(0.1)
        self._handlers: dict[int, Handler] = {}
        self._listeners: dict[int, Listener] = {}
        self._ids = 0
        self.lost = threading.Event()
        """Set when the gateway closes the connection."""
        self._held: list[str] | None = None
        self._reader: threading.Thread | None = None
        self.send({"op": "hello", "role": role, "name": name, "token": token, "client": "grid-engine"})
        welcome = json.loads(self.socket.recv())
        if welcome.get("op") != "welcome":
            raise SystemExit(f"grid engine: the gateway at {url} refused the hello: {welcome.get('message')}")
        self._reader = threading.Thread(target=self._read, name="gateway reader", daemon=True)
        self._reader.start()

    def send(self, frame: dict[str, Any]) -> None:
        """Send a frame; while the reader thread handles a query or sample, frames are held
        and go out together as one ``batch`` (a tick's events, state and reply: one message)."""
        text = json.dumps(frame)
        if self._held is not None and threading.current_thread() is self._reader:
            self._held.append(text)
        else:
            self.socket.send(text)

    def _handle(self, call: Callable[..., None], *args: Any) -> None:
        self._held = []
        try:
            call(*args)
        finally:
            held, self._held = self._held, None
            if len(held) == 1:
                self.socket.send(held[0])
            elif held:
                self.socket.send('{"op": "batch", "frames": [' + ", ".join(held) + "]}")

    def _next_id(self) -> int:
        self._ids += 1
        return self._ids

    def publish(self, key: str, message: dict[str, Any]) -> None:
        self.send({"op": "put", "key": key, "payload": message})

    def serve(self, key: str, handler: Handler) -> None:
        serve = self._next_id()
        self._handlers[serve] = handler
        self.send({"op": "serve", "id": serve, "key": key})

    def subscribe(self, key: str, listener: Listener) -> None:
        sub = self._next_id()
        self._listeners[sub] = listener
        self.send({"op": "subscribe", "id": sub, "key": key})

    def announce(self, role: str, name: str) -> None:
        """Nothing to do: the hello made the gateway declare the token."""

    def _read(self) -> None:
        from websockets.exceptions import ConnectionClosed

        try:
            for text in self.socket:
                frame = json.loads(text)
                op = frame.get("op")
                if op == "query":
                    self._handle(self._handlers[frame["serve"]], GatewayRequest(self, frame))
                elif op == "sample":
                    payload = frame.get("payload")
                    message = payload if isinstance(payload, dict) else MALFORMED
                    self._handle(self._listeners[frame["sub"]], message, frame["key"])
                elif op == "error":
                    print(
                        f"grid engine: the gateway refused a frame: {frame.get('message')}", file=sys.stderr
                    )
        except ConnectionClosed:
            pass
        print("grid engine: the gateway closed the connection", file=sys.stderr, flush=True)
        self.lost.set()

    def close(self) -> None:
        self._stack.close()
