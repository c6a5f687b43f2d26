"""The engine node on the wire: robot commands and statuses, control errors, real time."""

from __future__ import annotations

import queue
import time
from pathlib import Path

import pytest
from support import EngineProcess

from bridge import Bridge, LockstepClient, Received, RemoteError, handshake
from protocol import (
    Cell,
    CommandState,
    CommandStatus,
    ControlReply,
    ErrorCode,
    Navigate,
    Pause,
    Pick,
    Reset,
    Resume,
    RobotCommand,
    State,
    Step,
)


def test_robot_commands_over_the_wire(world: str) -> None:
    with EngineProcess(world, "--scenario", "paper-tidy"), Bridge(world) as brain:
        info = handshake(brain, client="test", role="brain", timeout=30.0)
        robot = next(a for a in info.scene.agents if a.kind.value == "robot")
        assert robot.acts, "paper-tidy's robot acts"
        statuses: queue.Queue[CommandStatus] = queue.Queue()
        brain.subscribe(brain.keys.status(robot.id), lambda s, _: statuses.put(s), expected=CommandStatus)
        clock = LockstepClient(brain, timeout=60.0)
        clock.reset(scenario="paper-tidy")
        commands = brain.publisher(brain.keys.command(robot.id))
        assert commands.wait_matched(10.0)

        def run(command: RobotCommand) -> list[CommandStatus]:
            commands.put(command)
            got: list[CommandStatus] = []
            for _ in range(600):  # people in paper-tidy may stand in the robot's way for a while
                clock.step(1)
                while not statuses.empty():
                    status = statuses.get()
                    if status.command == command.id:
                        got.append(status)
                if got and got[-1].state.final:
                    return got
            raise AssertionError(f"{command} never ended: {got}")

        went = run(RobotCommand(id="go", robot=robot.id, action=Navigate(cell=Cell(1, 8))))
        assert [s.state for s in went] == [
            CommandState.ACCEPTED,
            CommandState.RUNNING,
            CommandState.SUCCEEDED,
        ]
        picked = run(RobotCommand(id="grab", robot=robot.id, action=Pick(item="skate")))
        assert picked[-1].state is CommandState.SUCCEEDED
        impossible = run(RobotCommand(id="wall", robot=robot.id, action=Navigate(cell=Cell(3, 3))))
        assert [s.state for s in impossible] == [CommandState.FAILED] and "not walkable" in impossible[
            0
        ].reason
        # a command for a robot the scene lacks is failed on that robot's status key, where its
        # sender listens (the grid engine and the C# sample answer there too)
        ghost: queue.Queue[CommandStatus] = queue.Queue()
        brain.subscribe(brain.keys.status("ghost"), lambda s, _: ghost.put(s), expected=CommandStatus)
        to_ghost = brain.publisher(brain.keys.command("ghost"))
        assert to_ghost.wait_matched(10.0)
        to_ghost.put(RobotCommand(id="boo", robot="ghost", action=Navigate(cell=Cell(1, 8))))
        answer = ghost.get(timeout=30.0)
        assert answer.robot == "ghost" and answer.state is CommandState.FAILED, answer
        assert "unknown robot 'ghost'" in answer.reason, answer


def test_control_errors_and_bad_input_keep_the_engine_serving(world: str, tmp_path: Path) -> None:
    with EngineProcess(world, "--scenario", "paper-1"), Bridge(world) as client:
        handshake(client, client="test", timeout=30.0)
        key = client.keys.control
        with pytest.raises(RemoteError) as unknown:
            client.query(key, Reset(scenario="paper-99"), ControlReply)
        assert unknown.value.code is ErrorCode.UNKNOWN_SCENARIO and "paper-1" in unknown.value.message
        broken = tmp_path / "broken.toml"
        broken.write_text('name = "broken"\nmap = 42\n')
        with pytest.raises(RemoteError) as bad:
            client.query(key, Reset(scenario=str(broken)), ControlReply)
        assert bad.value.code is ErrorCode.BAD_REQUEST and "map: expected a map name, got 42" in str(
            bad.value
        ), f"a broken scenario file is named with what is wrong, not as unknown: {bad.value}"
        raw = list(client.session.get(key, payload=b'{"type":"step","protocol":"1.0","n":0}', timeout=5.0))
        assert raw and raw[0].err is not None and b"$.n" in raw[0].err.payload.to_bytes()
        client.session.put(client.keys.command("robot"), b"\x00garbage")
        reply = client.query(key, Step(n=3), ControlReply, timeout=5.0)
        assert reply.tick == 3 and reply.state is not None and reply.state.tick == 3


def test_realtime_runs_by_itself_and_pauses(world: str) -> None:
    with EngineProcess(world, "--scenario", "paper-1", "--realtime", "5"), Bridge(world) as client:
        info = handshake(client, client="test", timeout=30.0)
        assert info.clock.value == "realtime"
        ticks: queue.Queue[int] = queue.Queue()

        def on_state(state: State, _: Received) -> None:
            ticks.put(state.tick)

        client.subscribe(client.keys.state, on_state, expected=State)
        first = latest = ticks.get(timeout=30.0)
        # It runs by itself: 20 more ticks come without a step (0.4 s at 5x real time and 0.1 s
        # a tick). The bound is generous on purpose: a loaded machine may run slower than real
        # time, and the rate itself is measured by `toyroom bench`, not asserted here.
        deadline = time.monotonic() + 20.0
        while latest - first < 20 and time.monotonic() < deadline:
            try:
                latest = ticks.get(timeout=1.0)
            except queue.Empty:
                continue
        assert latest - first >= 20, f"expected 20 ticks to come by themselves, got {latest - first} in 20 s"
        with pytest.raises(RemoteError) as refused:
            client.query(client.keys.control, Step(n=1), ControlReply)
        assert refused.value.code is ErrorCode.UNSUPPORTED
        paused = client.query(client.keys.control, Pause(), ControlReply)
        assert paused.paused
        time.sleep(0.3)
        still = client.query(client.keys.control, Pause(), ControlReply).tick
        time.sleep(0.5)
        assert client.query(client.keys.control, Pause(), ControlReply).tick == still, (
            "paused engine kept ticking"
        )
        resumed = client.query(client.keys.control, Resume(), ControlReply)
        assert not resumed.paused
