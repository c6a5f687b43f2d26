"""The WebSocket gateway: real WebSocket clients (the ``websockets`` library) on one side, real
Zenoh sessions on loopback on the other."""

from __future__ import annotations

import json
import logging
import queue
import subprocess
import sys
import textwrap
import threading
import time
from collections.abc import Iterator
from contextlib import ExitStack
from pathlib import Path
from typing import Any

import jsonschema
import pytest
from support import golden_examples
from websockets.exceptions import ConnectionClosed
from websockets.sync.client import ClientConnection, connect

from bridge import Bridge, ConfigError, NoReply, Publisher, RemoteError, query
from protocol import Encoding, EngineInfo, Hello, Mind, State, Step
from protocol.schema import SCHEMA_DIR
from toyroom.gateway import Gateway, GatewaySettings, parse_listen

DEEP = "[" * 30000 + "]" * 30000
"""JSON nested deeper than any decoder goes (msgspec raises ``RecursionError`` on it)."""
DEEP_PUT = '{"op": "put", "key": "engine/state", "payload": ' + DEEP + "}"
FRAME_SCHEMAS = {path.stem: json.loads(path.read_text()) for path in (SCHEMA_DIR / "gateway").glob("*.json")}


class Client:
    """A WebSocket client of the gateway: frames in and out as dicts, each one the gateway
    sends checked against its JSON Schema."""

    def __init__(self, url: str) -> None:
        self._stack = ExitStack()
        self.socket: ClientConnection = self._stack.enter_context(connect(url, proxy=None, compression=None))

    def send(self, frame: dict[str, Any] | str) -> None:
        self.socket.send(frame if isinstance(frame, str) else json.dumps(frame))

    def recv(self, timeout: float = 5.0) -> dict[str, Any]:
        frame = json.loads(self.socket.recv(timeout=timeout))
        jsonschema.validate(frame, FRAME_SCHEMAS[frame["op"]])
        return frame

    def hello(self, name: str = "unity", token: str | None = None) -> dict[str, Any]:
        self.send({"op": "hello", "role": "engine", "name": name, "token": token})
        return self.recv()

    def error(self) -> dict[str, Any]:
        frame = self.recv()
        assert frame["op"] == "error", f"expected an error frame, got {frame}"
        return frame

    def close(self) -> None:
        self._stack.close()


@pytest.fixture
def gateway(world: str) -> Iterator[Gateway]:
    with Gateway(GatewaySettings(world=world, listen="ws://127.0.0.1:0")) as running:
        yield running


@pytest.fixture
def client(gateway: Gateway) -> Iterator[Client]:
    joined = Client(gateway.url)
    welcome = joined.hello()
    assert welcome["op"] == "welcome" and welcome["prefix"] == f"toyroom/{gateway.settings.world}", welcome
    yield joined
    joined.close()


def test_the_first_frame_must_be_hello(gateway: Gateway) -> None:
    anonymous = Client(gateway.url)
    anonymous.send({"op": "put", "key": "engine/state", "payload": {}})
    assert anonymous.error()["code"] == "not_welcome"
    assert anonymous.hello()["op"] == "welcome", "the connection should stay usable after a refusal"
    assert anonymous.hello()["code"] == "bad_frame", "a second hello should be refused"
    anonymous.close()


def test_a_frame_nested_too_deeply_is_refused_even_before_hello(
    gateway: Gateway, caplog: pytest.LogCaptureFixture
) -> None:
    """Not a close with 1011 and a traceback: an error frame, one warning, the link lives on."""
    caplog.set_level(logging.WARNING)
    anonymous = Client(gateway.url)
    for frame in (DEEP_PUT, '{"op": "hello", "role": "engine", "name": "x", "extra": ' + DEEP + "}"):
        anonymous.send(frame)
        error = anonymous.error()
        assert error["code"] == "bad_frame" and "nested too deeply" in error["message"], (
            f"expected bad_frame saying 'nested too deeply', got {error}"
        )
    assert anonymous.hello()["op"] == "welcome", "the connection should stay usable after the refusals"
    anonymous.close()
    tracebacks = [
        r.getMessage() for r in caplog.records if r.exc_info is not None or r.levelno >= logging.ERROR
    ]
    assert tracebacks == [], f"expected no error or traceback in the log, got {tracebacks}"
    refusals = [r.getMessage() for r in caplog.records if "nested too deeply" in r.getMessage()]
    assert len(refusals) == 2 and all("\n" not in m for m in refusals), (
        f"expected 2 one-line warnings: {refusals}"
    )


def test_a_token_file_is_required_of_every_client(world: str, tmp_path: Path) -> None:
    secret = tmp_path / "token"
    secret.write_text("s3cret\n")
    secret.chmod(0o600)
    with Gateway(GatewaySettings(world=world, listen="ws://127.0.0.1:0", token_file=secret)) as gateway:
        intruder = Client(gateway.url)
        refusal = intruder.hello(token="guess")
        assert refusal["op"] == "error" and refusal["code"] == "unauthorized", refusal
        with pytest.raises(ConnectionClosed) as closed:
            intruder.socket.recv(timeout=5)
        assert closed.value.rcvd is not None and closed.value.rcvd.code == 4001
        assert Client(gateway.url).hello(token="s3cret")["op"] == "welcome"
    empty = tmp_path / "empty"
    empty.write_text("  \n")
    empty.chmod(0o600)
    with pytest.raises(ConfigError, match="empty"):
        Gateway(GatewaySettings(world=world, listen="ws://127.0.0.1:0", token_file=empty))
    with pytest.raises(ConfigError, match="cannot read the --token file"):
        Gateway(GatewaySettings(world=world, listen="ws://127.0.0.1:0", token_file=tmp_path / "missing"))


@pytest.mark.parametrize(
    ("frame", "code", "says"),
    [
        ("garbage", "bad_frame", "JSON is malformed"),
        ({"op": "teleport"}, "bad_frame", "$.op"),
        ({"op": "put", "key": 3, "payload": {}}, "bad_frame", "$.key"),
        ({"op": "put", "key": "engine/*", "payload": {}}, "bad_key", "no wildcards"),
        ({"op": "put", "key": "/toyroom/x", "payload": {}}, "bad_key", "relative to the world"),
        ({"op": "put", "key": "@alive/engine/x", "payload": {}}, "bad_key", "liveliness"),
        ({"op": "put", "key": "engine/state", "payload": {"type": "state"}}, "bad_payload", "state"),
        (
            {"op": "put", "key": "engine/state", "payload": {"type": "nonsense", "protocol": "1.1"}},
            "bad_payload",
            "nonsense",
        ),
        ({"op": "reply", "qid": 99, "payload": {}}, "unknown_id", "99"),
        ({"op": "unsubscribe", "id": 7}, "unknown_id", "7"),
        ({"op": "get", "id": 1, "key": "engine/info", "timeout": -1}, "bad_frame", "timeout"),
        pytest.param(DEEP, "bad_frame", "Expected `object`, got `array`", id="nested-array"),
        pytest.param(DEEP_PUT, "bad_frame", "nested too deeply to decode", id="nested-payload"),
        pytest.param(
            '{"op": "put", "key": "engine/state", "payload": {"type": "state", "x": ' + DEEP + "}}",
            "bad_frame",
            "nested too deeply",
            id="nested-in-a-message",
        ),
    ],
)
def test_a_malformed_frame_gets_an_error_frame_and_the_link_lives_on(
    gateway: Gateway, client: Client, frame: dict[str, Any] | str, code: str, says: str
) -> None:
    with Bridge(gateway.settings.world) as bridge:
        states: queue.Queue[State] = queue.Queue()
        bridge.subscribe(bridge.keys.state, lambda m, _: states.put(m), expected=State)
        _route_states(client, states)
        client.send(frame)
        error = client.error()
        assert error["code"] == code and says in error["message"], (
            f"expected {code} saying {says!r}, got {error}"
        )
        state = golden_examples()["state"]
        client.send({"op": "put", "key": "engine/state", "payload": json.loads(_json(state))})
        assert _next_state(states).tick == state.tick, "a good put after the refusal did not arrive"


PROBE_TICKS = 1_000_000
"""Ticks from here up mark the states ``_route_states`` puts to open the route; tests skip them."""


def _route_states(client: Client, states: queue.Queue[State], timeout: float = 5.0) -> None:
    """Put probe states through the gateway until one reaches the test's subscriber: a Zenoh put
    made before the subscriber's declaration has reached the gateway's session is dropped, and
    that race is not what these tests are about. ``_next_state`` skips any late probe."""
    payload = json.loads(_json(golden_examples()["state"]))
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        client.send({"op": "put", "key": "engine/state", "payload": {**payload, "tick": PROBE_TICKS}})
        try:
            states.get(timeout=0.1)
            return
        except queue.Empty:
            continue
    raise AssertionError(f"no state put through the gateway reached a subscriber within {timeout} s")


def _next_state(states: queue.Queue[State], timeout: float = 5.0) -> State:
    """The next state that is not a probe of ``_route_states``."""
    deadline = time.monotonic() + timeout
    while (state := states.get(timeout=max(deadline - time.monotonic(), 0.0))).tick >= PROBE_TICKS:
        pass
    return state


def _json(message: Any) -> bytes:
    from protocol import encode

    return encode(message, Encoding.JSON)


def test_puts_subscriptions_and_messagepack(gateway: Gateway, client: Client) -> None:
    with Bridge(gateway.settings.world) as bridge:
        client.send({"op": "subscribe", "id": 5, "key": "brain/*"})
        publisher = bridge._track(Publisher(bridge.session, bridge.keys.mind, encoding=Encoding.MSGPACK))
        assert publisher.wait_matched(5), "the gateway's subscriber never matched"
        mind = golden_examples()["mind"]
        publisher.put(mind)
        sample = client.recv()
        assert sample["op"] == "sample" and sample["sub"] == 5 and sample["key"] == "brain/mind", sample
        assert sample["payload"] == json.loads(_json(mind)), "MessagePack should arrive as the same JSON"
        client.send({"op": "unsubscribe", "id": 5})
        client.send({"op": "unsubscribe", "id": 5})  # refused once the first one is done
        assert client.error()["code"] == "unknown_id"
        publisher.put(mind)
        with pytest.raises(TimeoutError):
            client.recv(timeout=0.5)
        assert isinstance(mind, Mind)


@pytest.mark.parametrize("encoding", [Encoding.JSON, Encoding.MSGPACK])
def test_a_served_key_answers_queries_in_their_encoding(
    gateway: Gateway, client: Client, encoding: Encoding
) -> None:
    info = golden_examples()["engine_info"]
    client.send({"op": "serve", "id": 1, "key": "engine/info"})
    client.send({"op": "serve", "id": 2, "key": "engine/control"})

    def engine() -> None:
        for _ in range(2):
            frame = client.recv()
            if frame["key"] == "engine/info":
                assert frame["payload"]["type"] == "hello", frame
                client.send({"op": "reply", "qid": frame["qid"], "payload": json.loads(_json(info))})
            else:
                refusal = {"type": "error", "protocol": "1.1", "code": "bad_request", "message": "no steps"}
                client.send({"op": "reply", "qid": frame["qid"], "ok": False, "payload": refusal})

    worker = threading.Thread(target=engine)
    worker.start()
    with Bridge(gateway.settings.world) as bridge:
        _await_queryable(bridge, bridge.keys.info)
        _await_queryable(bridge, bridge.keys.control)
        got = query(
            bridge.session, bridge.keys.info, Hello(client="t", role="brain"), EngineInfo, encoding=encoding
        )
        assert got == info
        with pytest.raises(RemoteError, match="no steps") as refused:
            query(bridge.session, bridge.keys.control, Step(n=1), EngineInfo, encoding=encoding)
        assert refused.value.code.value == "bad_request"
    worker.join(5)


def test_a_lost_client_is_a_lost_engine_within_a_second(gateway: Gateway) -> None:
    """Killed (the socket closes) and hung (it stops answering pings): the token goes either way,
    and a query it held ends at once with nobody answering (as when a Zenoh engine dies),
    instead of waiting out its 10 s timeout."""
    script = textwrap.dedent(
        f"""
        import json, sys, time
        from websockets.sync.client import connect
        ws = connect({gateway.url!r}, proxy=None).__enter__()
        ws.send(json.dumps({{"op": "hello", "role": "engine", "name": sys.argv[1]}}))
        ws.recv()
        ws.send(json.dumps({{"op": "serve", "id": 1, "key": "engine/control"}}))
        print("ready", flush=True)
        while json.loads(ws.recv())["op"] != "query":
            pass
        print("held", flush=True)
        time.sleep(60)
        """
    )
    with Bridge(gateway.settings.world) as bridge:
        watcher = bridge.presence("engine")
        for name, how in (("killed", "SIGKILL"), ("hung", "SIGSTOP")):
            child = subprocess.Popen([sys.executable, "-c", script, name], stdout=subprocess.PIPE, text=True)
            try:
                assert child.stdout is not None and child.stdout.readline().strip() == "ready"
                assert watcher.wait_alive(name, timeout=5), f"{name}: the token never appeared"
                held: queue.Queue[BaseException | None] = queue.Queue()
                _await_queryable(bridge, bridge.keys.control)
                threading.Thread(target=_ask, args=(bridge, held), daemon=True).start()
                assert child.stdout.readline().strip() == "held", f"{name}: the query never reached it"
                lost_at = time.monotonic()
                getattr(child, "kill" if how == "SIGKILL" else "send_signal")(
                    *(() if how == "SIGKILL" else (__import__("signal").SIGSTOP,))
                )
                assert watcher.wait_gone(name, timeout=1.5), f"{name}: still alive 1.5 s later"
                gone = time.monotonic() - lost_at
                assert gone < 1.5, f"{name}: noticed after {gone:.2f} s"
                err = held.get(timeout=5)
                assert isinstance(err, NoReply) and "nobody answers" in str(err), f"{name}: got {err!r}"
            finally:
                child.kill()
                child.wait()


def _await_queryable(bridge: Bridge, key: str, timeout: float = 5.0) -> None:
    """Wait until ``bridge``'s session knows of a queryable on ``key`` (a query sent before
    that is answered by nobody)."""
    querier = bridge.session.declare_querier(key)
    try:
        deadline = time.monotonic() + timeout
        while not querier.matching_status.matching:  # type: ignore[attr-defined]
            assert time.monotonic() < deadline, f"no queryable on {key} within {timeout} s"
            time.sleep(0.01)
    finally:
        querier.undeclare()


def _ask(bridge: Bridge, answers: queue.Queue[BaseException | None]) -> None:
    """Send one ``step`` and put what came of it (``None``: an answer) in ``answers``."""
    try:
        query(bridge.session, bridge.keys.control, Step(n=1), EngineInfo, timeout=10)
        answers.put(None)
    except BaseException as err:  # noqa: BLE001 - handed to the test thread
        answers.put(err)


def test_get_collects_the_answers(gateway: Gateway, client: Client) -> None:
    info = golden_examples()["engine_info"]
    with Bridge(gateway.settings.world) as bridge:
        bridge.queryable(bridge.keys.info, lambda request, key: info)
        hello = json.loads(_json(Hello(client="unity", role="engine")))
        deadline = time.monotonic() + 5  # until the queryable's declaration reaches the gateway
        while True:
            client.send({"op": "get", "id": 4, "key": "engine/info", "payload": hello, "timeout": 5})
            replies = client.recv()
            if replies.get("replies") or time.monotonic() > deadline:
                break
        assert replies["op"] == "replies" and replies["id"] == 4, replies
        assert [r["payload"] for r in replies["replies"]] == [json.loads(_json(info))]
        assert replies["replies"][0]["ok"] and replies["replies"][0]["key"] == "engine/info"
    client.send({"op": "get", "id": 5, "key": "nobody/here", "timeout": 0.3})
    assert client.recv() == {"op": "replies", "id": 5, "replies": []}


def test_bad_settings_are_named(world: str, gateway: Gateway) -> None:
    with pytest.raises(ConfigError, match="ws://HOST:PORT"):
        parse_listen("http://127.0.0.1:7448")
    with pytest.raises(ConfigError, match="port"):
        parse_listen("ws://127.0.0.1:99999")
    taken = gateway.url
    with pytest.raises(ConfigError, match=f"cannot listen on {taken}"):
        Gateway(GatewaySettings(world=world, listen=taken))


def test_the_command_names_a_bad_listen_url(world: str) -> None:
    result = subprocess.run(
        [sys.executable, "-m", "toyroom", "gateway", "--world", world, "--listen", "tcp/127.0.0.1:1"],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert result.returncode == 2 and "ws://HOST:PORT" in result.stderr, result.stderr


def test_a_batch_is_acted_on_in_order_and_a_bad_frame_in_it_is_refused_alone(
    gateway: Gateway, client: Client
) -> None:
    with Bridge(gateway.settings.world) as bridge:
        states: queue.Queue[State] = queue.Queue()
        bridge.subscribe(bridge.keys.state, lambda m, _: states.put(m), expected=State)
        _route_states(client, states)
        state = json.loads(_json(golden_examples()["state"]))
        later = {**state, "tick": state["tick"] + 1}
        client.send(
            {
                "op": "batch",
                "frames": [
                    {"op": "put", "key": "engine/state", "payload": state},
                    {"op": "put", "key": "engine/*", "payload": state},
                    {"op": "put", "key": "engine/state", "payload": later},
                ],
            }
        )
        assert client.error()["code"] == "bad_key"
        ticks = [_next_state(states).tick, _next_state(states).tick]
        assert ticks == [state["tick"], state["tick"] + 1], f"expected both good puts in order, got {ticks}"
