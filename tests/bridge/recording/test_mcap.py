"""MCAP recordings: Foxglove-ready channels, the same mind from a recording as live, and a
recorder killed mid-run that still holds all but the last second."""

from __future__ import annotations

import json
import signal
import subprocess
import sys
import time
from pathlib import Path

from mcap.reader import make_reader
from support import EngineProcess, toyroom_run

from bridge import Bridge, LockstepClient, handshake
from bridge.recording.mcap import read_mcap


def test_recorded_run_opens_and_gives_the_same_mind(tmp_path: Path) -> None:
    recording = tmp_path / "run.mcap"
    live = toyroom_run(tmp_path / "live", "paper-2", "--robot", "observe", "--record", str(recording))
    with recording.open("rb") as handle:
        reader = make_reader(handle)
        summary = reader.get_summary()
        assert summary is not None, "a finished recording has a summary"
        schemas = {s.name: s for s in summary.schemas.values()}
        assert {"toyroom.state", "toyroom.event", "toyroom.mind", "toyroom.engine_info"} <= set(schemas)
        assert all(s.encoding == "jsonschema" for s in schemas.values())
        assert json.loads(schemas["toyroom.state"].data)["$ref"] == "#/$defs/State"
        topics = {c.topic for c in summary.channels.values()}
        assert any(t.endswith("/engine/state") for t in topics) and any(
            t.endswith("/brain/mind") for t in topics
        )
        assert all(c.message_encoding == "json" for c in summary.channels.values())
    again = tmp_path / "again"
    result = subprocess.run(
        [sys.executable, "-m", "toyroom", "infer", str(recording), "--out", str(again)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert result.returncode == 0, result.stderr
    assert (again / "mind.csv").read_text() == (live / "mind.csv").read_text()


def test_killed_recorder_keeps_all_but_the_last_second(world: str, tmp_path: Path) -> None:
    recording = tmp_path / "cut.mcap"
    with EngineProcess(world, "--scenario", "paper-1"), Bridge(world) as client:
        handshake(client, client="test", timeout=30.0)
        recorder = subprocess.Popen(
            [sys.executable, "-m", "toyroom", "record", "--world", world, str(recording)],
            stdout=subprocess.PIPE,
            text=True,
        )
        try:
            assert recorder.stdout is not None and "toyroom record" in recorder.stdout.readline()
            clock = LockstepClient(client, timeout=10.0)
            clock.reset(scenario="paper-1")
            stepped: list[tuple[int, float]] = []
            start = time.monotonic()
            while time.monotonic() - start < 3.0:
                state = clock.step(1)
                stepped.append((state.tick, time.monotonic()))
                time.sleep(0.02)
            killed_at = time.monotonic()
            recorder.send_signal(signal.SIGKILL)
            recorder.wait(timeout=10)
        finally:
            if recorder.poll() is None:
                recorder.kill()
    recorded = {json.loads(r.data)["tick"] for r in read_mcap(recording) if r.key.endswith("/engine/state")}
    must_have = [tick for tick, at in stepped if at < killed_at - 1.0]
    missing = [tick for tick in must_have if tick not in recorded]
    assert len(must_have) > 20 and missing == [], (
        f"{len(missing)} states older than 1 s were lost: {missing[:10]}"
    )
