"""A slow subscriber (a viewer or recorder that cannot keep up) never slows the engine:
states are sent drop-on-congestion."""

from __future__ import annotations

import threading
import time

from support import EngineProcess

from bridge import Bridge, LockstepClient, Received, handshake
from protocol import State


def test_a_stalled_state_subscriber_does_not_stall_lockstep(world: str) -> None:
    stalled = []
    finished = threading.Event()

    def very_slow(state: State, _: Received) -> None:
        stalled.append(state.tick)
        finished.wait(0.5)  # half a second per state while the test runs; then its backlog drains at
        # once (it used to hold the test process up to 150 s at exit: the states are queued, not dropped)

    with EngineProcess(world, "--scenario", "paper-1"), Bridge(world) as slow, Bridge(world) as driver:
        handshake(driver, client="test", timeout=30.0)
        slow.subscribe(slow.keys.state, very_slow, expected=State)
        clock = LockstepClient(driver, timeout=60.0)
        clock.reset(scenario="paper-1")
        started = time.monotonic()
        for _ in range(300):
            clock.step(1)
        elapsed = time.monotonic() - started
        handled = len(stalled)
        finished.set()
    # blocked by the subscriber, 300 states would take 150 s; dropping, the engine runs on
    assert elapsed < 30, f"300 lock-step ticks took {elapsed:.1f} s behind a stalled subscriber"
    assert handled < 300, "the slow subscriber cannot have handled every state by then"
