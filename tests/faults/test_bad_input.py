"""Random and mutated messages thrown at every key of a running engine and brain: both stay
up and keep serving good messages."""

from __future__ import annotations

import json
import subprocess
import sys
import threading
import time
from collections.abc import Iterator

import pytest
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from support import EngineProcess, golden_examples

from bridge import Bridge, Received, handshake
from protocol import Mind, ProtocolError, State, decode, encode

KEYS = [
    "engine/info",
    "engine/control",
    "engine/state",
    "engine/events",
    "engine/truth",
    "robot/robot/command",
    "robot/robot/status",
    "brain/mind",
]
GOLDEN = [encode(m) for m in golden_examples().values()]


@pytest.fixture(scope="module")
def running(tmp_path_factory: pytest.TempPathFactory) -> Iterator[tuple[str, subprocess.Popen[str], Bridge]]:
    world = "fuzz-target"
    with EngineProcess(world, "--scenario", "paper-robot", "--realtime", "1"):
        brain = subprocess.Popen(
            [sys.executable, "-m", "brain", "--world", world, "--log-level", "ERROR", "--timeout", "30"],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        with Bridge(world) as bridge:
            handshake(bridge, client="fuzzer", timeout=30.0)
            try:
                yield world, brain, bridge
            finally:
                brain.terminate()
                brain.wait(timeout=10)


def is_valid_message(payload: bytes) -> bool:
    try:
        decode(payload)
    except ProtocolError:
        return False
    return True


def mutate(data: bytes, edits: list[tuple[int, int]]) -> bytes:
    out = bytearray(data)
    for pos, value in edits:
        if out:
            out[pos % len(out)] = value
    return bytes(out)


payloads = st.one_of(
    st.binary(max_size=300),
    st.builds(
        mutate,
        st.sampled_from(GOLDEN),
        st.lists(st.tuples(st.integers(0, 5000), st.integers(0, 255)), max_size=6),
    ),
    st.builds(
        lambda d, v: json.dumps({**json.loads(d), "protocol": v}).encode(),
        st.sampled_from(GOLDEN),
        st.sampled_from(["2.0", "0.1", "x", "1.9"]),
    ),
)


@settings(max_examples=150, deadline=None, suppress_health_check=[HealthCheck.function_scoped_fixture])
@given(key=st.sampled_from(KEYS), payload=payloads, as_query=st.booleans())
def test_garbage_everywhere(
    running: tuple[str, subprocess.Popen[str], Bridge], key: str, payload: bytes, as_query: bool
) -> None:
    # a payload that decodes is a valid message (a pause, a reset, a state of another
    # episode: "1.9" is a compatible minor version), which the nodes rightly obey
    assume(not is_valid_message(payload))
    _, _, bridge = running
    full = f"{bridge.keys.prefix}/{key}"
    if as_query:
        list(bridge.session.get(full, payload=payload, timeout=2.0))
    else:
        bridge.session.put(full, payload)


def test_both_still_serve_after_the_fuzzing(running: tuple[str, subprocess.Popen[str], Bridge]) -> None:
    _, brain, bridge = running
    got = {"state": threading.Event(), "mind": threading.Event()}

    def on_state(_: State, __: Received) -> None:
        got["state"].set()

    def on_mind(_: Mind, __: Received) -> None:
        got["mind"].set()

    bridge.subscribe(bridge.keys.state, on_state, expected=State)
    bridge.subscribe(bridge.keys.mind, on_mind, expected=Mind)
    assert handshake(bridge, client="after-fuzz", timeout=10.0).engine.startswith("sim2d")
    assert got["state"].wait(10), "the engine stopped publishing states"
    assert got["mind"].wait(10), "the brain stopped publishing its estimates"
    time.sleep(0.2)
    assert brain.poll() is None, f"the brain died: {brain.stderr.read() if brain.stderr else ''}"
