"""The engine conformance kit against every engine the repository has, and against
deliberately broken variants (each must fail, naming the check)."""

from __future__ import annotations

import subprocess
import sys

import pytest
from support import EngineProcess, GridEngineProcess

from bridge import Bridge
from bridge.conformance import check_engine

SIM2D_SCENARIOS = [
    "paper-1",
    "paper-2",
    "paper-3",
    "paper-robot",
    "paper-robot-decline",
    "paper-tidy",
    "sally-anne",
]


def _assert_all_pass(world: str) -> None:
    with Bridge(world) as bridge:
        results = check_engine(bridge, timeout=10.0)
    failed = [r.line() for r in results if not r.passed]
    assert failed == [], "\n".join(failed)
    assert [r.name for r in results][:5] == ["handshake", "scene", "liveliness", "reset", "stepping"]


@pytest.mark.parametrize("scenario", SIM2D_SCENARIOS)
def test_sim2d_conforms(world: str, scenario: str) -> None:
    with EngineProcess(world, "--scenario", scenario):
        _assert_all_pass(world)


@pytest.mark.parametrize("scenario", ["paper-robot", "sally-anne"])
def test_grid_engine_conforms(world: str, scenario: str) -> None:
    with GridEngineProcess(world, "--scenario", scenario):
        _assert_all_pass(world)


@pytest.mark.parametrize(
    ("fault", "check", "says"),
    [
        ("version", "handshake", "the peer speaks 2.0"),
        ("status", "robot commands", "expected accepted -> running -> succeeded"),
        ("double-step", "stepping", "expected tick 1, got 2"),
    ],
)
def test_broken_engines_fail_the_named_check(world: str, fault: str, check: str, says: str) -> None:
    with GridEngineProcess(world, "--scenario", "paper-robot", "--break", fault):
        result = subprocess.run(
            [sys.executable, "-m", "bridge", "conform", "--world", world, "--timeout", "10"],
            capture_output=True,
            text=True,
            timeout=300,
        )
    assert result.returncode != 0, f"a '{fault}' engine passed:\n{result.stdout}"
    failures = [line for line in result.stdout.splitlines() if line.startswith("FAIL")]
    assert any(line.startswith(f"FAIL  {check}:") and says in line for line in failures), result.stdout


def test_conform_command_passes_and_the_token_goes_with_the_engine(world: str) -> None:
    engine = EngineProcess(world, "--scenario", "paper-robot")
    with Bridge(world) as watcher_side:
        watcher = watcher_side.presence("engine")
        result = subprocess.run(
            [sys.executable, "-m", "bridge", "conform", "--world", world, "--timeout", "10"],
            capture_output=True,
            text=True,
            timeout=300,
        )
        assert result.returncode == 0, result.stdout + result.stderr
        assert "0 failed" in result.stdout
        assert watcher.wait_alive("sim2d", timeout=5.0)
        engine.close()
        assert watcher.wait_gone("sim2d", timeout=2.0), "the engine's liveliness token outlived it"
