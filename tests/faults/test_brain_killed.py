"""A brain that dies while the robot drives: the engine keeps running, and the robot body
stops once the brain's heartbeat has been missing for its timeout (1 s). The 'brain' here
is a client process of the test's own that commands a long drive, beats for a while, then
is killed; the real brain's heartbeats keep its robot going (tests/brain/test_free_run.py)."""

from __future__ import annotations

import queue
import signal
import subprocess
import sys
import textwrap
import time

from support import EngineProcess

from bridge import Bridge, Received, handshake
from protocol import CommandState, CommandStatus, State

BRAIN = textwrap.dedent(
    """
    import sys, time
    from bridge import Bridge, handshake
    from protocol import Cell, Heartbeat, Navigate, RobotCommand
    with Bridge(sys.argv[1]) as bridge:
        handshake(bridge, client="little-brain", timeout=30)
        commands = bridge.publisher(bridge.keys.command("robot"))
        beats = bridge.publisher(bridge.keys.heartbeat("robot"))
        commands.wait_matched(10)
        commands.put(RobotCommand(id="far", robot="robot", action=Navigate(cell=Cell(0, 10))))
        print("driving", flush=True)
        seq = 0
        while True:
            beats.put(Heartbeat(robot="robot", seq=seq))
            seq += 1
            time.sleep(0.25)
    """
)


def test_robot_stops_when_its_brain_dies(world: str) -> None:
    statuses: queue.Queue[tuple[float, CommandStatus]] = queue.Queue()
    latest: list[State] = []
    with EngineProcess(world, "--scenario", "paper-robot", "--realtime", "1"), Bridge(world) as watcher:
        handshake(watcher, client="test", timeout=30.0)
        watcher.subscribe(
            watcher.keys.status("robot"),
            lambda s, _: statuses.put((time.monotonic(), s)),
            expected=CommandStatus,
        )

        def on_state(state: State, _: Received) -> None:
            latest[:] = [state]

        watcher.subscribe(watcher.keys.state, on_state, expected=State)
        brain = subprocess.Popen([sys.executable, "-c", BRAIN, world], stdout=subprocess.PIPE, text=True)
        try:
            assert brain.stdout is not None and brain.stdout.readline().strip() == "driving"
            time.sleep(2.0)  # driving, with heartbeats: nothing may stop it
            seen = []
            while not statuses.empty():
                seen.append(statuses.get()[1].state)
            assert CommandState.RUNNING in seen and CommandState.FAILED not in seen, seen
            killed_at = time.monotonic()
            brain.send_signal(signal.SIGKILL)
            brain.wait(timeout=30)
            at, status = statuses.get(timeout=30)
            assert status.command == "far" and status.state is CommandState.FAILED, status
            assert "no heartbeat" in status.reason, status.reason
            assert at - killed_at < 2.5, f"the robot stopped {at - killed_at:.2f} s after its brain died"
            tick = latest[0].tick
            time.sleep(0.5)
            assert latest[0].tick > tick, "the engine should keep running without a brain"
        finally:
            if brain.poll() is None:
                brain.kill()
