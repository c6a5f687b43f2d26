"""A lock-step step that gets no answer (the engine process frozen with SIGSTOP) times out
with a clear error instead of hanging. (With the timeout disabled, a step waits for an
engine that is slow but alive, as at a breakpoint: tests/bridge/test_lockstep.py.)"""

from __future__ import annotations

import signal
import time

import psutil
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
            # a signal is delivered when the process is next scheduled: on a loaded machine a
            # step sent at once could still be answered (it was: DID NOT RAISE StepTimeout)
            stopped = psutil.Process(engine.process.pid)
            deadline = time.monotonic() + 10
            while stopped.status() != psutil.STATUS_STOPPED:
                assert time.monotonic() < deadline, f"the engine never stopped: {stopped.status()}"
                time.sleep(0.01)
            started = time.monotonic()
            with pytest.raises(StepTimeout) as caught:
                hasty.step(1)
            # it gives up after its 1 s timeout, not never; generous for a loaded machine
            waited = time.monotonic() - started
            assert waited < 10.0, f"expected the step to give up after about 1 s, it took {waited:.1f} s"
            message = str(caught.value)
            assert "timeout 1 s" in message and "last state: episode" in message and "timeout=None" in message

        finally:
            engine.process.send_signal(signal.SIGCONT)
        again = LockstepClient(bridge, timeout=60.0)
        deadline = time.monotonic() + 15
        while True:  # the engine runs again: the link comes back and stepping resumes
            try:
                assert again.step(1).tick >= 1
                break
            except StepTimeout:
                assert time.monotonic() < deadline, "stepping never resumed after SIGCONT"
                time.sleep(0.2)
