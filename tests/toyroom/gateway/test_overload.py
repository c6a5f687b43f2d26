"""Issue 64, items 5 and 7: a client that never reads holds up nobody (it is dropped, the others
get every state), and a frame above the gateway's limit is named to whoever asked, not
taken for a missing engine. Real gateways (a process, or in this process), real WebSocket
clients, real Zenoh sessions on loopback."""

from __future__ import annotations

import json
import logging
import threading
from collections.abc import Iterator
from contextlib import ExitStack
from typing import Any

import pytest
from support import golden_examples
from websockets.exceptions import ConnectionClosed
from websockets.sync.client import ClientConnection, connect

from bridge import Bridge, RemoteError, handshake
from protocol import Encoding, encode
from protocol.limits import MAX_FRAME_BYTES
from toyroom.bench.gateway_load import stalled_reader, summary_line
from toyroom.gateway import Gateway, GatewaySettings

pytestmark = pytest.mark.process

STATE = json.loads(encode(golden_examples()["state"], Encoding.JSON))
TOO_BIG = MAX_FRAME_BYTES + 1024
"""Bytes of the reply frame an engine sends in the last test, 1 KiB above the gateway's limit."""


def _check_load(result: dict[str, Any], stalled_line: str) -> None:
    """The stalled reader was dropped (one log line, ``stalled_line`` at its start), its token
    withdrawn, and every live reader got every state in order and was never dropped."""
    said = summary_line(result)
    assert "after_s" in result["stalled"], f"the stalled reader's liveliness token never went: {said}"
    assert len(result["dropped"]) == 1 and result["dropped"][0].startswith(stalled_line), (
        f"expected one line '{stalled_line}...', got {result['dropped']}"
    )
    assert result["states"] > result["stalled"]["after_states"], f"no state was sent after the drop: {said}"
    for name, live in result["live"].items():
        assert live["closed"] is None and live["every_state_in_order"], (
            f"expected {name} to get all {result['states']} states in order, not dropped; "
            f"got {live['received']}, closed: {live['closed']} ({said})"
        )


def test_a_stalled_reader_is_dropped_and_the_others_get_every_state() -> None:
    """Two live readers and one that never reads, at 500 states a second, the gateway's ping
    long enough that only its queue of 256 frames can drop the stalled one: it goes with one
    line naming it and the queue, its token with it, and the live readers get every state,
    500 of them after the drop. Before, the stalled reader's full socket held up the Zenoh
    thread that sent to it, and every other client with it."""
    result = stalled_reader(
        STATE,
        readers=2,
        seconds=120.0,
        rate=500.0,
        gateway_options=["--ping", "60", "--queue-frames", "256"],
        after=500,
    )
    _check_load(result, "client viewer/stalled dropped: too slow: 256 frames queued")
    assert result["stalled"]["closed"] in ("cut (no close frame)", "1008 too slow: 256 frames queued"), (
        f"expected the stalled reader closed with 1008 'too slow' or cut, got {result['stalled']['closed']}"
    )


@pytest.mark.sweep
def test_four_readers_get_every_state_at_full_rate_beside_a_stalled_one() -> None:
    """The load test: four live readers and a stalled one, an engine putting 1000 states a
    second (beyond a lock-step engine through the gateway, 786 us a tick in
    docs/performance.md) for 20 s, the gateway's defaults: the stalled reader is dropped and
    every live reader gets every state, so never more than the queue's 4096 frames behind
    (the lag in ms is measured by ``python -m toyroom.bench.gateway --stalled-reader``)."""
    result = stalled_reader(STATE, readers=4, seconds=20.0, rate=1000.0)
    _check_load(result, "client viewer/stalled dropped: ")


def _join(stack: ExitStack, url: str, role: str, name: str) -> ClientConnection:
    socket = stack.enter_context(connect(url, proxy=None, compression=None, close_timeout=0.5))
    socket.send(json.dumps({"op": "hello", "role": role, "name": name}))
    assert json.loads(socket.recv(timeout=10))["op"] == "welcome"
    return socket


@pytest.fixture
def gateway(world: str) -> Iterator[Gateway]:
    with Gateway(GatewaySettings(world=world, listen="ws://127.0.0.1:0")) as running:
        yield running


def test_a_flooding_engine_that_leaves_goes_at_once_and_newcomers_are_served(gateway: Gateway) -> None:
    """The issue's run: a client subscribed to everything that never reads, an engine putting
    3000 states of 8 kB (24 MB, more than the sockets' buffers hold) as fast as it can and
    closing its socket, then a fresh engine and reader: the flooder's token goes, and the
    reader gets all 20 of the fresh engine's states. Before, the gateway stalled on the
    non-reader: the reader got none, the token went 18 s late."""
    with ExitStack() as stack, Bridge(gateway.settings.world) as bridge:
        engines = bridge.presence("engine")
        stalled = _join(stack, gateway.url, "viewer", "stalled")
        stalled.send(json.dumps({"op": "subscribe", "id": 1, "key": "**"}))
        flooder = _join(stack, gateway.url, "engine", "flooder")
        assert engines.wait_alive("flooder", timeout=10), "the flooder's token never appeared"
        frame = {"op": "put", "key": "engine/state"}
        for tick in range(3000):  # an unknown field pads each state, as a newer engine's may
            flooder.send(json.dumps({**frame, "payload": {**STATE, "tick": tick, "pad": "x" * 8000}}))
        flooder.close()
        reader = _join(stack, gateway.url, "viewer", "reader")
        reader.send(json.dumps({"op": "subscribe", "id": 1, "key": "engine/state"}))
        fresh = _join(stack, gateway.url, "engine", "fresh")
        ticks = _serve_twenty(fresh, reader)
        assert ticks == list(range(10_000, 10_020)), f"expected the 20 fresh states in order, got {ticks}"
        assert engines.wait_gone("flooder", timeout=10), "the flooder's token outlived its socket by 10 s"


def _serve_twenty(engine: ClientConnection, reader: ClientConnection) -> list[int]:
    """Probe until the reader gets a state from ``engine`` (its subscription is in place),
    then put ticks 10000-10019 and return the ticks the reader got after the probe."""
    frame = {"op": "put", "key": "engine/state"}
    while True:
        engine.send(json.dumps({**frame, "payload": {**STATE, "tick": 99_999}}))
        try:
            if json.loads(reader.recv(timeout=0.2))["payload"]["tick"] == 99_999:
                break
        except TimeoutError:
            continue
    for tick in range(10_000, 10_020):
        engine.send(json.dumps({**frame, "payload": {**STATE, "tick": tick}}))
    ticks: list[int] = []
    while len(ticks) < 20:
        tick = json.loads(reader.recv(timeout=20))["payload"]["tick"]
        if tick != 99_999:
            ticks.append(tick)
    return ticks


def test_a_frame_above_the_limit_is_named_to_whoever_asked(
    gateway: Gateway, caplog: pytest.LogCaptureFixture
) -> None:
    """An engine behind the gateway answers the handshake with a frame above the 16 MiB limit:
    the gateway drops it (1009) with one warning, and the brain's handshake reads an error
    that names the frame's size and the limit, at once. Before, it read "no engine answered
    the handshake ... is an engine of this world running?" after its whole timeout."""
    caplog.set_level(logging.WARNING, logger="toyroom.gateway")
    with ExitStack() as stack, Bridge(gateway.settings.world) as bridge:
        engine = _join(stack, gateway.url, "engine", "huge")
        engine.send(json.dumps({"op": "serve", "id": 1, "key": "engine/info"}))
        threading.Thread(target=_answer_too_big, args=(engine,), daemon=True).start()
        with pytest.raises(RemoteError) as refused:
            handshake(bridge, client="test", timeout=10)
    message = str(refused.value)
    assert (
        f"above the gateway's limit of {MAX_FRAME_BYTES:,} bytes" in message and "engine/huge" in message
    ), f"expected the refusal to name the client and the limit, got {message!r}"
    assert f"frame with {TOO_BIG} bytes" in message, f"expected the frame's size, {TOO_BIG}: {message!r}"
    dropped = [r.getMessage() for r in caplog.records if "dropped" in r.getMessage()]
    assert len(dropped) == 1 and "client engine/huge dropped: frame with" in dropped[0], (
        f"expected one warning naming the client, got {dropped}"
    )


def _answer_too_big(engine: ClientConnection) -> None:
    """Answer the first query with a reply frame of :data:`TOO_BIG` bytes (the gateway may
    close the connection while it is sent)."""
    query = json.loads(engine.recv(timeout=30))
    head = f'{{"op":"reply","qid":{query["qid"]},"payload":"'
    try:
        engine.send(head + "x" * (TOO_BIG - len(head) - 2) + '"}')
    except ConnectionClosed:
        pass
