"""Random and mutated messages thrown at every key of a running engine and brain: both stay
up and keep serving good messages."""

from __future__ import annotations

import json
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from dataclasses import dataclass

import pytest
from hypothesis import HealthCheck, assume, example, given, settings
from hypothesis import strategies as st
from support import EngineProcess, golden_examples

from bridge import Bridge, Received, handshake
from protocol import ErrorCode, ErrorReply, Mind, ProtocolError, State, decode, encode

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
seen_refusals: list[str] = []
GOLDEN = [encode(m) for m in golden_examples().values()]


@dataclass
class Running:
    """The engine and the brain under fire, and the bridge that fires."""

    engine: EngineProcess
    brain: subprocess.Popen[str]
    bridge: Bridge

    def dead(self) -> str | None:
        """Which node has exited, with its output, or None while both run."""
        if self.engine.process.poll() is not None:
            return f"the engine exited ({self.engine.process.returncode}): {self.engine.output()[-2000:]}"
        if self.brain.poll() is not None:
            err = self.brain.stderr.read() if self.brain.stderr else ""
            return f"the brain exited ({self.brain.returncode}): {err[-2000:]}"
        return None


@pytest.fixture(scope="module")
def running(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Running]:
    world = "fuzz-target"
    with EngineProcess(world, "--scenario", "paper-robot", "--realtime", "1") as engine:
        brain = subprocess.Popen(
            [sys.executable, "-m", "brain", "--world", world, "--log-level", "ERROR", "--timeout", "30"],
            stdout=subprocess.PIPE,
            stderr=subprocess.PIPE,
            text=True,
        )
        with Bridge(world) as bridge:
            handshake(bridge, client="fuzzer", timeout=30.0)
            try:
                yield Running(engine, brain, bridge)
            finally:
                brain.terminate()
                brain.wait(timeout=30)


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
@example(key="engine/control", payload=b"", as_query=True)  # a query without payload: no garbage
@example(key="engine/control", payload=b"\x00", as_query=True)
def test_garbage_everywhere(running: Running, key: str, payload: bytes, as_query: bool) -> None:
    """Each piece of garbage leaves both nodes running, and a request on the engine's control
    key is refused with an ``error`` reply that says why."""
    # a payload that decodes is a valid message (a pause, a reset, a state of another
    # episode: "1.9" is a compatible minor version), which the nodes rightly obey
    assume(not is_valid_message(payload))
    bridge = running.bridge
    full = f"{bridge.keys.prefix}/{key}"
    if as_query:
        replies = list(bridge.session.get(full, payload=payload, timeout=2.0))
        # a refused request, never silence or a success; a query without payload is no garbage:
        # it asks the engine's clock (answered with a control reply)
        if key == "engine/control" and payload:
            seen_refusals.append(key)
            refusals = [_refusal(reply) for reply in replies]
            assert refusals and all(r is not None for r in refusals), (
                f"expected an error reply to garbage on {key}, got {replies}"
            )
            assert {r.code for r in refusals if r is not None} <= {
                ErrorCode.BAD_REQUEST,
                ErrorCode.VERSION_MISMATCH,
            }, f"expected bad_request or version_mismatch, got {refusals}"
    else:
        bridge.session.put(full, payload)
    assert running.dead() is None, running.dead()


def _refusal(reply: object) -> ErrorReply | None:
    """The ``error`` reply a query got, or None when it got a success."""
    err = getattr(reply, "err", None)
    if err is None:
        return None
    return decode(err.payload.to_bytes(), ErrorReply)


def test_both_still_serve_after_the_fuzzing(running: Running) -> None:
    brain, bridge = running.brain, running.bridge
    got = {"state": threading.Event(), "mind": threading.Event()}

    def on_state(_: State, __: Received) -> None:
        got["state"].set()

    def on_mind(_: Mind, __: Received) -> None:
        got["mind"].set()

    bridge.subscribe(bridge.keys.state, on_state, expected=State)
    bridge.subscribe(bridge.keys.mind, on_mind, expected=Mind)
    assert seen_refusals, "the fuzzing never queried the engine's control key: it checked no refusal"
    assert handshake(bridge, client="after-fuzz", timeout=30.0).engine.startswith("sim2d")
    assert got["state"].wait(10), "the engine stopped publishing states"
    assert got["mind"].wait(10), "the brain stopped publishing its estimates"
    time.sleep(0.2)
    assert brain.poll() is None, f"the brain died: {brain.stderr.read() if brain.stderr else ''}"
