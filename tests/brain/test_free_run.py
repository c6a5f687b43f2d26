"""The brain against a real-time engine: it free-runs on the newest state and still acts."""

from __future__ import annotations

import threading
from pathlib import Path

from support import EngineProcess, run_brain

from bridge import Bridge, Received
from protocol import Event, EventKind


def test_brain_follows_a_realtime_engine(world: str, tmp_path: Path) -> None:
    seen: list[Event] = []
    lock = threading.Lock()

    def on_event(event: Event, _: Received) -> None:
        with lock:
            seen.append(event)

    with EngineProcess(world, "--scenario", "paper-robot", "--realtime", "10"), Bridge(world) as watcher:
        watcher.subscribe(watcher.keys.events, on_event, expected=Event)
        brain = run_brain(world, "--scenario", "paper-robot", "--out", str(tmp_path))
    assert brain.returncode == 0, brain.stderr
    with lock:
        gives = [(e.actor, e.item, e.target) for e in seen if e.kind is EventKind.GIVE]
    assert ("robot", "skate", "A1") in gives and ("robot", "ball", "A2") in gives, gives
    assert (tmp_path / "mind.csv").stat().st_size > 0
