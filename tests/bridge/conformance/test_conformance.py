"""The engine conformance kit against every engine the repository has, and against
deliberately broken variants (each must fail, naming the check)."""

from __future__ import annotations

import subprocess
import sys
import uuid
from collections.abc import Callable, Iterator
from pathlib import Path

import pytest
from support import CSharpEngineProcess, EngineProcess, GatewayProcess, GridEngineProcess

from bridge import Bridge
from bridge.conformance import Check, Probe
from bridge.conformance.commands import (
    check_cancel,
    check_command_while_one_runs,
    check_navigation,
    check_robot_commands,
    check_say_several,
    check_status_order,
)
from bridge.conformance.handshake import check_handshake, check_liveliness, check_scene
from bridge.conformance.stepping import check_control_reply, check_stepping
from bridge.conformance.suite import EngineConformance
from bridge.conformance.wire import check_event_order, check_messagepack

GRID_ENGINE = Path(__file__).resolve().parents[3] / "examples" / "grid_engine" / "main.py"

SIM2D_SCENARIOS = [
    "paper-1",
    "paper-2",
    "paper-3",
    "paper-robot",
    "paper-robot-decline",
    "paper-tidy",
    "sally-anne",
    "paper-auto",
]


class TestSim2d(EngineConformance):
    """sim2d on every bundled scenario."""

    @pytest.fixture(scope="class", params=SIM2D_SCENARIOS)
    @classmethod
    def conformance_world(cls, request: pytest.FixtureRequest) -> Iterator[str]:
        world = f"conform-{request.param}-{uuid.uuid4().hex[:6]}"
        with EngineProcess(world, "--scenario", request.param):
            yield world


class TestGridEngine(EngineConformance):
    """The example grid engine, written from the protocol documents alone."""

    @pytest.fixture(scope="class", params=["paper-robot", "sally-anne"])
    @classmethod
    def conformance_world(cls, request: pytest.FixtureRequest) -> Iterator[str]:
        world = f"grid-{request.param}-{uuid.uuid4().hex[:6]}"
        with GridEngineProcess(world, "--scenario", request.param):
            yield world


class TestGridEngineThroughTheGateway(EngineConformance):
    """The grid engine without Zenoh: JSON frames over a WebSocket to ``toyroom gateway``."""

    @pytest.fixture(scope="class")
    @classmethod
    def conformance_world(cls) -> Iterator[str]:
        world = f"gateway-{uuid.uuid4().hex[:6]}"
        with GatewayProcess(world) as gateway, GridEngineProcess(world, "--gateway", gateway.url):
            yield world


class TestCSharpEngine(EngineConformance):
    """The C# SDK's grid engine under Mono, through the gateway (clients/unity/)."""

    @pytest.fixture(scope="class", params=["paper-robot", "sally-anne"])
    @classmethod
    def conformance_world(
        cls, request: pytest.FixtureRequest, tmp_path_factory: pytest.TempPathFactory
    ) -> Iterator[str]:
        world = f"csharp-{request.param}-{uuid.uuid4().hex[:6]}"
        folder = tmp_path_factory.mktemp("scenarios")
        with GatewayProcess(world) as gateway, CSharpEngineProcess(gateway.url, folder, request.param):
            yield world


class TestSim2dRealtime(EngineConformance):
    """sim2d free-running at 4x: the clock, pause and resume, heartbeat loss, and every robot
    command check (in real time since issue 56)."""

    strict = True

    @pytest.fixture(scope="class")
    @classmethod
    def conformance_world(cls) -> Iterator[str]:
        world = f"conform-realtime-{uuid.uuid4().hex[:6]}"
        with EngineProcess(world, "--scenario", "paper-robot", "--realtime", "4"):
            yield world


class TestGridEngineRealtime(EngineConformance):
    """The grid engine on its own clock (``--realtime``, a tick every 0.1 s): every check but
    reset, stepping and the control reply, the robot's among them."""

    strict = True

    @pytest.fixture(scope="class")
    @classmethod
    def conformance_world(cls) -> Iterator[str]:
        world = f"grid-realtime-{uuid.uuid4().hex[:6]}"
        with GridEngineProcess(world, "--scenario", "paper-robot", "--realtime", "--tick-seconds", "0.1"):
            yield world


BROKEN: dict[str, tuple[Callable[[Probe], str], str]] = {
    "version": (check_handshake, "the peer speaks 2.0"),
    "status": (check_robot_commands, "expected accepted -> running -> succeeded"),
    "double-step": (check_stepping, "expected tick 1, got 2"),
    "extra-tick": (check_stepping, "expected tick 1, got 2"),
    "refuse-commands": (check_navigation, "expected succeeded, got ['failed(refused)']"),
    "omit-lists": (check_control_reply, "expected the control_reply of a step to carry its last state"),
    "events-after-state": (check_event_order, "expected each tick's events before its state"),
    "duplicate-status": (check_status_order, "expected accepted -> running -> one final status"),
    "never-arrive": (check_navigation, "expected a final status within 400 ticks"),
    "ignore-cancel": (check_cancel, "expected the cancel succeeded and the navigate cancelled"),
    "drop-queued": (check_command_while_one_runs, "expected a status (accepted or failed), got none"),
    "wrong-encoding": (check_messagepack, "expected a MessagePack reply, got application/json"),
    "no-visibility": (check_scene, "visibility"),
    "door-in-region": (check_scene, "door"),
    "no-token": (check_liveliness, "expected a liveliness token"),
    "say-one": (check_say_several, "expected a say event per item on one tick"),
}
"""Each ``--break`` mode of the grid engine: the check function that must fail, and what it
must say."""
ROBOT_BREAKS = (
    "status",
    "refuse-commands",
    "duplicate-status",
    "never-arrive",
    "ignore-cancel",
    "drop-queued",
    "say-one",
)
"""The modes that concern the robot: real time must catch them at the same check."""


def conform(world: str, timeout: int) -> subprocess.CompletedProcess[str]:
    """``toyroom conform`` against the engine of ``world`` (``timeout``: seconds per check)."""
    return subprocess.run(
        [sys.executable, "-m", "toyroom", "conform", "--world", world, "--timeout", str(timeout)],
        capture_output=True,
        text=True,
        timeout=300,
    )


def test_every_break_mode_is_listed_and_tested() -> None:
    listed = subprocess.run(
        [sys.executable, str(GRID_ENGINE), "--break", "list"], capture_output=True, text=True, timeout=60
    )
    modes = [line.split()[0] for line in listed.stdout.splitlines() if line.strip()]
    assert len(modes) >= 12 and set(modes) == set(BROKEN), f"--break list: {modes}; tested: {sorted(BROKEN)}"


@pytest.mark.parametrize("fault", sorted(BROKEN))
def test_broken_engines_fail_the_named_check(world: str, fault: str) -> None:
    fails_at(world, fault)


@pytest.mark.sweep  # a conform run in real time per fault, 5-120 s each: `make sweeps` (tests/tiers.py)
@pytest.mark.parametrize("fault", ROBOT_BREAKS)
def test_broken_robots_fail_the_named_check_in_real_time(world: str, fault: str) -> None:
    """The robot's faults caught in real time too, at the same check (the grid engine on its
    own clock, a tick every 0.02 s, so that a navigation that never arrives is given its 400
    ticks in 16 s)."""
    fails_at(world, fault, "--realtime", "--tick-seconds", "0.02")


def fails_at(world: str, fault: str, *clock: str) -> None:
    """The grid engine broken with ``fault`` fails ``toyroom conform`` at the check named in
    :data:`BROKEN`, saying what it says there."""
    function, says = BROKEN[fault]
    check = Check(function).name
    if clock:
        says = says.replace("within 400 ticks", "within 400 ticks of real time")
    with GridEngineProcess(world, "--scenario", "paper-robot", "--break", fault, *clock):
        result = conform(world, 5)
    assert result.returncode != 0, f"a '{fault}' engine passed:\n{result.stdout}"
    failures = [line for line in result.stdout.splitlines() if line.startswith("FAIL")]
    assert any(line.startswith(f"FAIL  {check}:") and says in line for line in failures), (
        f"expected 'FAIL  {check}: ...{says}...', got:\n" + "\n".join(failures)
    )


def test_conform_command_passes_and_the_token_goes_with_the_engine(world: str) -> None:
    engine = EngineProcess(world, "--scenario", "paper-robot")
    with Bridge(world) as watcher_side:
        watcher = watcher_side.presence("engine")
        result = conform(world, 10)
        assert result.returncode == 0, result.stdout + result.stderr
        assert "0 failed" in result.stdout
        assert watcher.wait_alive("sim2d", timeout=5.0)
        engine.close()
        assert watcher.wait_gone("sim2d", timeout=2.0), "the engine's liveliness token outlived it"


def test_a_protocol_1_1_engine_still_passes_conform(world: str) -> None:
    """Minor versions only add optional fields: an engine stamping 1.1 on every message passes
    the kit of this side (the current version), with the difference said once, not failed."""
    with GridEngineProcess(world, "--scenario", "paper-robot", "--speak", "1.1"):
        result = conform(world, 10)
    assert result.returncode == 0, result.stdout + result.stderr
    assert "0 failed" in result.stdout, result.stdout
    assert "1.1" in result.stdout + result.stderr, "the minor-version difference should be said"
