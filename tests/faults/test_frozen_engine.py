"""A frozen or paused engine. A lock-step step that gets no answer (the engine process frozen
with SIGSTOP) times out with a clear error instead of hanging, and once the engine runs again
the step asked again is carried out once. (With the timeout disabled, a step waits for an
engine that is slow but alive, as at a breakpoint: tests/bridge/test_lockstep.py.) An engine
paused past its lease, as at an editor's breakpoint, is lost to its brain for the pause, and
the brain carries the episode on where it left off (the sweep of 20 such pauses under load:
test_pause_sweep.py)."""

from __future__ import annotations

import signal
import threading
import time
from pathlib import Path

import psutil
import pytest
from support import BrainProcess, EngineProcess, handled, long_paper_2, pause

from bridge import Bridge, LockstepClient, StepTimeout, handshake
from protocol import State

PAUSE_S = 12.0
"""How long the brain's engine is paused: past its lease (8 s, ``toyroom run``'s), the brain's
step timeout (10 s) and Zenoh's time to open a link (10 s), so the pause sets off what a
minute's does: the brain's link to the engine goes down after 8 s, and the brain waits. The
pause's length matters no more after that: pauses of 3 s (past an 800 ms lease) and of 60 s
(past 8 s) were seen to end the same way, the link back within a tenth of a second of SIGCONT."""
PAUSED_AT = 100
"""The engine is paused once a state of this tick is out (of about 240)."""


def test_frozen_engine_times_out_then_the_step_asked_again_is_carried_out_once(world: str) -> None:
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
        # the engine runs again, and may have carried out the step it read once continued (its
        # answer lost: the link went down under the stop): asked again, it is carried out once
        deadline = time.monotonic() + 15
        while True:
            try:
                state = hasty.again()
                break
            except StepTimeout:  # the link is not back yet
                assert time.monotonic() < deadline, "stepping never resumed after SIGCONT"
                time.sleep(0.2)
        assert state.tick == 1, (
            f"the step asked again should give tick 1 (carried out once); got {state.tick}"
        )


def test_an_engine_paused_past_its_lease_is_carried_on_where_it_was_left(world: str, tmp_path: Path) -> None:
    """The engine paused for :data:`PAUSE_S` mid-episode: the brain must take it for gone, wait,
    and carry the episode on once it is continued: the very states and events of a run without
    the pause, every tick once (the engine is deterministic in lock-step).

    The brain's own lease is a minute, so the engine, continued, reads the step the brain sent
    into the pause before it can notice the brain's link went down, and carries it out, its
    answer lost: the harder of the two ways a pause ends, every time. (With equal leases it
    drops the link first in about half the runs, and the step with it; before request ids
    the brain then failed in the other half, 'stepped from tick 100 to 101 ... while its link
    to the brain was down'. The sweep has equal leases: both ways.)"""
    scenario = long_paper_2(tmp_path, 200, "long")
    args = ("--scenario", str(scenario), "--lease-ms", "60000")
    with EngineProcess(world, "--lease-ms", "8000"):
        baseline = BrainProcess(world, *args, "--run-log", str(tmp_path / "baseline"))
        with baseline:
            assert baseline.finish(120) == 0, f"the run without a pause failed:\n{baseline.output()}"
    out = tmp_path / "paused"
    with EngineProcess(world, "--lease-ms", "8000") as engine, Bridge(world) as watcher:
        reached = threading.Event()
        watcher.subscribe(
            watcher.keys.state, lambda s, _: reached.set() if s.tick >= PAUSED_AT else None, expected=State
        )
        with BrainProcess(world, *args, "--run-log", str(out)) as brain:
            assert reached.wait(60), f"no tick {PAUSED_AT} within 60 s:\n{brain.output()}"
            pause(engine.process, PAUSE_S)
            status = brain.finish(120)
            output = brain.output()
    lines = [line for line in output.splitlines() if line.strip()]
    assert status == 0, (
        f"after a {PAUSE_S:g} s pause the brain should carry the episode on (exit 0); it exited "
        f"{status}: {lines[-1] if lines else '(no output)'}"
    )
    assert "lost" in output and "the episode carries on" in output, (
        f"the brain should have taken the engine for gone in the pause, then carried on; it said:\n{output}"
    )
    got, want = handled(out), handled(tmp_path / "baseline")
    ticks = [r["tick"] for r in got if r["type"] == "state"]
    assert ticks == list(range(len(ticks))), f"every tick once expected; the brain handled {ticks}"
    first = next(
        (i for i, (a, b) in enumerate(zip(got, want, strict=False)) if a != b), min(len(got), len(want))
    )
    assert got == want, (
        f"the {len(want)} states and events of the run without a pause were expected; got {len(got)}, "
        f"the first difference at #{first}: {got[first : first + 1]} instead of {want[first : first + 1]}"
    )


def test_an_engine_lost_past_the_lost_timeout_fails_the_run_in_one_line(world: str, tmp_path: Path) -> None:
    """``--lost-timeout``: an engine gone (paused past its 800 ms lease) for longer than the
    brain's lost timeout fails the run with one line naming it, instead of a wait with no end
    (an evaluation then runs it again); without it the brain waits, as the test above does."""
    scenario = long_paper_2(tmp_path, 200, "long")
    with EngineProcess(world, "--lease-ms", "800") as engine, Bridge(world) as watcher:
        reached = threading.Event()
        watcher.subscribe(
            watcher.keys.state, lambda s, _: reached.set() if s.tick >= PAUSED_AT else None, expected=State
        )
        with BrainProcess(world, "--scenario", str(scenario), "--lost-timeout", "2") as brain:
            assert reached.wait(60), f"no tick {PAUSED_AT} within 60 s:\n{brain.output()}"
            engine.process.send_signal(signal.SIGSTOP)
            try:
                status = brain.finish(90)
            finally:
                engine.process.send_signal(signal.SIGCONT)
            output = brain.output()
    assert status == 2, f"expected exit 2, the engine lost past 2 s; got {status}:\n{output[-2000:]}"
    assert "lost for 2 s and not back" in output, f"expected the lost engine named, got:\n{output[-2000:]}"


@pytest.mark.parametrize("bad", ["-1", "nan", "inf", "soon"])
def test_a_bad_lost_timeout_is_refused_naming_it(bad: str, capsys: pytest.CaptureFixture[str]) -> None:
    from brain.__main__ import run_parser

    with pytest.raises(SystemExit) as exited:
        run_parser().parse_args(["--lost-timeout", bad])
    said = capsys.readouterr().err
    assert exited.value.code == 2, f"expected exit 2 for --lost-timeout {bad}, got {exited.value.code}"
    assert "--lost-timeout" in said and "number >= 0" in said, f"expected option and bound: {said!r}"
    assert run_parser().parse_args(["--lost-timeout", "60"]).lost_timeout == 60.0
