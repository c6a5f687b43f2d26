"""Random and mutated messages thrown at every key of a running engine and brain: both stay
up and keep serving good messages."""

from __future__ import annotations

import json
import os
import re
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path

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


# ----- bad command lines: refused in one line, before anything starts --------------------------

BAD_WORLDS = ["**", "a/b", "*", "$", "", "é", "abc\n"]
"""World names that are no key chunk (a wildcard, a separator, a Zenoh special, nothing,
not ASCII, a trailing newline)."""


def refused(*args: str, timeout: float = 60) -> str:
    """``toyroom ARGS`` refused: exit 2, one line on stderr and no traceback, nothing on
    stdout (nothing started); that line. A command that hangs fails the test after
    ``timeout`` s (it is killed)."""
    command = [sys.executable, "-m", "toyroom", *args]
    # a process group of its own: one that hangs is killed with whatever it started
    process = subprocess.Popen(
        command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, start_new_session=True
    )
    try:
        stdout, stderr = process.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(process.pid, signal.SIGKILL)
        stdout, stderr = process.communicate()
        pytest.fail(f"expected `toyroom {' '.join(args)}` to be refused at once; it hung: {stderr!r}")
    lines = stderr.splitlines()
    assert process.returncode == 2 and len(lines) == 1 and stdout == "", (
        f"expected `toyroom {' '.join(args)}` to exit 2 with one line on stderr and nothing on stdout; "
        f"got {process.returncode}, stderr {stderr!r}, stdout {stdout!r}"
    )
    return lines[0]


@pytest.mark.parametrize(
    "command",
    [
        ["sim"],
        ["brain"],
        ["view"],
        ["gateway", "--listen", "ws://127.0.0.1:0"],
        ["run", "--no-live"],
        ["record", "x.mcap"],
        ["replay", "x.mcap"],
        ["conform"],
        ["doctor"],
    ],
    ids=lambda command: command[0],
)
def test_every_command_refuses_a_world_that_is_no_name(command: list[str], tmp_path: Path) -> None:
    out = tmp_path / "out"
    args = [a if a != "x.mcap" else str(tmp_path / a) for a in command]
    line = refused(*args, "--world", "**", *(["--out", str(out)] if command[0] == "run" else []))
    assert "--world" in line and "'**'" in line, f"expected the refusal to name --world '**', got {line!r}"
    assert not out.exists(), f"expected `toyroom run` to start nothing, but it made {sorted(out.rglob('*'))}"


@pytest.mark.parametrize("command", ["sim", "view"])
@pytest.mark.parametrize("name", BAD_WORLDS, ids=repr)
def test_sim_and_view_refuse_every_bad_world_name(command: str, name: str) -> None:
    line = refused(command, "--world", name)
    assert f"got {name!r}" in line, f"expected the refusal to name {name!r}, got {line!r}"


def token_refusal(world: str, token: Path) -> str:
    """What ``toyroom gateway --token TOKEN`` says as it refuses to start."""
    return refused("gateway", "--world", world, "--listen", "ws://127.0.0.1:0", "--token", str(token))


@pytest.mark.parametrize("mode", [0o666, 0o644, 0o640, 0o604, 0o620], ids=lambda mode: f"{mode:04o}")
def test_a_token_file_others_may_read_or_change_is_refused(world: str, tmp_path: Path, mode: int) -> None:
    """As ssh refuses a private key others can read: the file and its mode are named."""
    token = tmp_path / "token"
    token.write_text("s3cret\n")
    token.chmod(mode)
    line = token_refusal(world, token)
    assert str(token) in line and f"mode {mode:04o}" in line and "chmod 600" in line, (
        f"expected the refusal to name {token} and its mode {mode:04o}, got {line!r}"
    )


def test_a_token_file_of_no_text_or_no_file_is_refused(world: str, tmp_path: Path) -> None:
    """Bytes that are not UTF-8, a FIFO (nobody writes: an open would wait forever), a folder."""
    binary = tmp_path / "binary"
    binary.write_bytes(b"\xff\xfe\x00s3cret")
    binary.chmod(0o600)
    fifo = tmp_path / "fifo"
    os.mkfifo(fifo, 0o600)
    folder = tmp_path / "folder"
    folder.mkdir(mode=0o700)
    for path, says in ((binary, "not UTF-8"), (fifo, "a FIFO, not a regular file"), (folder, "a folder")):
        line = token_refusal(world, path)
        assert str(path) in line and says in line, (
            f"expected the refusal to name {path} and say {says!r}, got {line!r}"
        )


def test_a_scenario_or_map_that_is_a_fifo_is_refused(world: str, tmp_path: Path) -> None:
    """Nobody writes to the FIFO: reading it would wait forever (deaf to SIGTERM)."""
    os.mkfifo(tmp_path / "fifo.map.toml")
    os.mkfifo(tmp_path / "fifo.toml")
    bundled = Path(__file__).parents[2] / "sim2d" / "scenarios" / "paper-1.toml"
    scenario = tmp_path / "scenario.toml"
    scenario.write_text(re.sub(r'(?m)^map = ".*"', 'map = "fifo.map.toml"', bundled.read_text()))
    cases = ((scenario, tmp_path / "fifo.map.toml"), (tmp_path / "fifo.toml", tmp_path / "fifo.toml"))
    for path, fifo in cases:
        line = refused("sim", "--world", world, "--scenario", str(path))
        assert str(fifo) in line and "a FIFO, not a regular file" in line, (
            f"expected the refusal to name {fifo} as a FIFO, got {line!r}"
        )
