"""A malformed frame on a participant's WebSocket gets an ``error`` frame, and their world runs
on: the server as a process, its world (sim2d engine and brain over loopback Zenoh), and a
real WebSocket client in place of the page (no browser needed)."""

from __future__ import annotations

import json
import re
import subprocess
import sys
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from websockets.exceptions import ConnectionClosed
from websockets.sync.client import ClientConnection, connect

from bridge.recording.readable import read_recording
from tests.toyroom.output import OutputLines
from toyroom.play import play_metadata

DEEP = "[" * 30000 + "]" * 30000
"""JSON nested deeper than Python's decoder goes (``json.loads`` raises ``RecursionError``)."""
BAD_FRAMES = (
    DEEP,
    "not json",
    '{"type": "key", "key": "ArrowRight", "pressed": NaN}',
    '{"type": "teleport"}',
)
STARTUP = 180.0
"""Seconds a world may take to start (engine and brain processes) on a loaded 2-core machine."""


class Server:
    """``toyroom play`` as a process, one participant, its output lines collected."""

    def __init__(self, out: Path, scenario: str = "paper-robot") -> None:
        command = [sys.executable, "-m", "toyroom", "play", "--scenario", scenario, "--as", "A1",
                   "--participants", "1", "--listen", "127.0.0.1:0", "--out", str(out), "--rate", "2",
                   "--grace", "1", "--log-level", "WARNING"]  # fmt: skip
        self.out = out
        self.process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
        self.output = OutputLines(self.process, "toyroom play")
        self.lines = self.output.lines

    def line(self, text: str, timeout: float) -> str:
        return self.output.wait(re.escape(text), timeout)


@pytest.fixture(scope="module")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    running = Server(tmp_path_factory.mktemp("play-frames"))
    try:
        yield running
    finally:
        running.process.terminate()
        try:
            running.process.wait(timeout=30)
        except subprocess.TimeoutExpired:
            running.process.kill()
            running.process.wait(timeout=10)


def _next(socket: ClientConnection, want: str, timeout: float) -> dict[str, Any]:
    """The next frame of type ``want`` (views keep coming meanwhile); fails on an ended world."""
    while True:
        try:
            message = json.loads(socket.recv(timeout=timeout))
        except ConnectionClosed as closed:
            raise AssertionError(
                f"expected a '{want}' frame, but the server closed the link: {closed}"
            ) from None
        if message.get("ended"):
            raise AssertionError(f"expected a '{want}' frame, but the world ended: {message['ended']!r}")
        if message.get("type") == want or (want == "view" and "tick" in message):
            return message


def test_a_malformed_frame_gets_an_error_and_the_world_runs_on(server: Server) -> None:
    """Also: the world waits for Start (a key before it is not sent; the layout carries the
    study's instructions and goal), and a second connection on the same link takes over: the
    first is told, and its frames are no longer taken."""
    link = server.line("participant p1: http", 60).split(": ", 2)[-1]
    url = link.replace("http://", "ws://").replace("/play/", "/ws/")
    with connect(url, open_timeout=30, max_size=None) as first:
        layout = _next(first, "scene", STARTUP)
        study = layout.get("study") or {}
        assert "Agent 1" in study.get("instructions", "") and "skate" in study.get("goal", ""), layout.get(
            "study"
        )
        assert layout.get("colours", {}).get("A1"), f"no colour for A1 in the layout: {layout.get('colours')}"
        waiting = _next(first, "view", STARTUP)
        assert waiting["started"] is False, waiting
        first.send(json.dumps({"type": "key", "key": "ArrowLeft", "pressed": 0.5}))  # before Start: not sent
        with connect(url, open_timeout=30, max_size=None) as socket:
            told = _next(first, "taken_over", 30)
            assert "another tab" in told["message"], told
            first.send(json.dumps({"type": "start"}))
            refused = _next(first, "error", 30)
            assert refused["message"].startswith("not taken"), refused
            _next(socket, "view", 30)
            socket.send(json.dumps({"type": "start"}))
            view = _next(socket, "view", 30)
            while not view["started"]:
                view = _next(socket, "view", 30)
            before = view["tick"]
            assert before <= waiting["tick"] + 2, (
                f"the clock ran before Start: tick {waiting['tick']} waiting, {before} at the start"
            )
            for frame in BAD_FRAMES:
                socket.send(frame)
                error = _next(socket, "error", 30)
                assert "not a key press" in error["message"] or "'pressed'" in error["message"], (
                    f"expected an error naming the bad frame {frame[:30]!r}, got {error}"
                )
            socket.send(json.dumps({"type": "key", "key": "ArrowRight", "pressed": 1.5}))
            later = _next(socket, "view", 30)
            while later["tick"] <= before + 5:
                later = _next(socket, "view", 30)
    report = server.line("participant p1: recording", 120)
    assert "incomplete: the page was closed" in report, (
        f"expected the world to end only for the page: {report}"
    )
    meta = play_metadata(server.out / "p1.mcap")
    assert meta is not None and "could not start" not in meta["reason"], f"p1's play metadata: {meta}"
    assert meta["outcome"] == "incomplete", meta
    report_md = server.out / "p1" / "report.md"
    assert (server.out / "p1" / "mind.csv").is_file() and report_md.is_file(), (
        "the brain of an incomplete world should still write mind.csv and report.md (issue 55)"
    )
    assert "before the episode's end" in report_md.read_text(encoding="utf-8")
    keys = [
        message.key
        for key, message in read_recording(server.out / "p1.mcap").messages()
        if key.endswith("/person/A1/command")
    ]
    assert keys == ["ArrowRight"], f"expected the good key press after the bad frames recorded, got {keys}"
    code = server.process.wait(timeout=60)
    assert code == 0, f"the server did not exit 0 once the world ended (got {code}): {server.lines[-30:]}"
    tracebacks = [line for line in server.lines if "Traceback" in line]
    assert tracebacks == [], f"expected no traceback from the server, got: {server.lines}"


def test_a_study_that_asks_for_consent_starts_only_with_it(tmp_path: Path) -> None:
    """A ``[study]`` with a ``consent`` text: Start without the box ticked is refused, saying
    so; with it, the clock starts."""
    from sim2d.scenario.maps import SCENARIO_DIR

    text = (SCENARIO_DIR / "paper-robot.toml").read_text(encoding="utf-8")
    text = text.replace('map = "paper"', f'map = "{(SCENARIO_DIR / "paper.map.toml").as_posix()}"')
    scenario = tmp_path / "consenting.toml"
    scenario.write_text(text.replace("time_limit = 400", 'time_limit = 400\nconsent = "You agree."'))
    running = Server(tmp_path / "out", str(scenario))
    try:
        link = running.line("participant p1: http", 60).split(": ", 2)[-1]
        url = link.replace("http://", "ws://").replace("/play/", "/ws/")
        with connect(url, open_timeout=30, max_size=None) as socket:
            layout = _next(socket, "scene", STARTUP)
            assert (layout.get("study") or {}).get("consent") == "You agree.", layout.get("study")
            _next(socket, "view", STARTUP)
            socket.send(json.dumps({"type": "start", "consented": False}))
            refused = _next(socket, "error", 30)
            assert "consent" in refused["message"], refused
            socket.send(json.dumps({"type": "start", "consented": True}))
            view = _next(socket, "view", 30)
            while not view["started"]:
                view = _next(socket, "view", 30)
    finally:
        running.process.terminate()
        running.process.wait(timeout=60)
