"""A slow subscriber (a viewer or recorder that cannot keep up) never slows the engine:
states are sent drop-on-congestion."""

from __future__ import annotations

import time

from support import EngineProcess

from bridge import Bridge, LockstepClient, Received, handshake
from protocol import State


def test_a_stalled_state_subscriber_does_not_stall_lockstep(world: str) -> None:
    stalled = []

    def very_slow(state: State, _: Received) -> None:
        stalled.append(state.tick)
        time.sleep(0.5)  # a subscriber that takes half a second per state

    with EngineProcess(world, "--scenario", "paper-1"), Bridge(world) as slow, Bridge(world) as driver:
        handshake(driver, client="test", timeout=30.0)
        slow.subscribe(slow.keys.state, very_slow, expected=State)
        clock = LockstepClient(driver, timeout=10.0)
        clock.reset(scenario="paper-1")
        started = time.monotonic()
        for _ in range(300):
            clock.step(1)
        elapsed = time.monotonic() - started
    # blocked by the subscriber, 300 states would take 150 s; dropping, the engine runs on
    assert elapsed < 30, f"300 lock-step ticks took {elapsed:.1f} s behind a stalled subscriber"
    assert len(stalled) < 300, "the slow subscriber cannot have handled every state"
