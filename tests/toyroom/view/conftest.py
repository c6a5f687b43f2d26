"""A world worth a screenshot: sim2d free-running and a brain publishing minds on it."""

from __future__ import annotations

import subprocess
import sys
import threading
from collections.abc import Iterator

import pytest
from support import EngineProcess

from bridge import Bridge
from protocol import Mind


@pytest.fixture
def living_world(world: str) -> Iterator[str]:
    """``world`` with sim2d running paper-1 in real time and a brain following it; yields once
    the brain's first mind has been published."""
    minded = threading.Event()
    with EngineProcess(world, "--scenario", "paper-1", "--realtime", "1"), Bridge(world) as watcher:
        watcher.subscribe(watcher.keys.mind, lambda *_: minded.set(), expected=Mind)
        brain = subprocess.Popen(
            [sys.executable, "-m", "brain", "--world", world, "--log-level", "WARNING"],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.PIPE,
        )
        try:
            if not minded.wait(90):
                brain.kill()
                pytest.fail(f"the brain published no mind within 90 s:\n{brain.communicate()[1].decode()}")
            yield world
        finally:
            brain.terminate()
            try:
                brain.wait(timeout=15)
            except subprocess.TimeoutExpired:
                brain.kill()
                brain.wait(timeout=10)
