"""A lock-step step that gets no answer (the engine process frozen with SIGSTOP) times out
with a clear error instead of hanging. (With the timeout disabled, a step waits for an
engine that is slow but alive, as at a breakpoint: tests/bridge/test_lockstep.py.)"""

from __future__ import annotations

import signal
import time

import pytest
from support import EngineProcess

from bridge import Bridge, LockstepClient, StepTimeout, handshake


def test_frozen_engine_times_out_then_a_patient_client_waits(world: str) -> None:
    with EngineProcess(world, "--scenario", "paper-1") as engine, Bridge(world) as bridge:
        handshake(bridge, client="test", timeout=30.0)
        hasty = LockstepClient(bridge, timeout=1.0)
        hasty.reset(scenario="paper-1")
        engine.process.send_signal(signal.SIGSTOP)
        try:
            started = time.monotonic()
            with pytest.raises(StepTimeout) as caught:
                hasty.step(1)
            assert time.monotonic() - started < 3.0
            message = str(caught.value)
            assert "timeout 1 s" in message and "last state: episode" in message and "timeout=None" in message

        finally:
            engine.process.send_signal(signal.SIGCONT)
        again = LockstepClient(bridge, timeout=10.0)
        deadline = time.monotonic() + 15
        while True:  # the engine runs again: the link comes back and stepping resumes
            try:
                assert again.step(1).tick >= 1
                break
            except StepTimeout:
                assert time.monotonic() < deadline, "stepping never resumed after SIGCONT"
                time.sleep(0.2)
