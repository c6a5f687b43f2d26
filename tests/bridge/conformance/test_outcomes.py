"""``toyroom conform`` tells skipped checks from passed ones: it prints passed, skipped (each
with its reason), failed and not-applicable counts, and ``--strict`` fails on a skip. A check
chooses what it exercises from the state it sees: with every item in a person's hands, the
pick-place-give check is skipped saying so, instead of failing a correct engine."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

from support import EngineProcess

from bridge.conformance.checks import CHECK_NAMES

HELD = """
name = "held"
map = "paper"
description = "A1 carries the only item and never puts it down."
robot = "act"

[[items]]
id = "car"
shape = "board"
at = "A1"

[[agents]]
id = "A1"
kind = "person"
name = "Agent 1"
script = [{ do = "wait" }]

[[agents]]
id = "robot"
kind = "robot"
name = "Robot"
"""
"""A scene whose robot acts, and whose only item a person holds for good."""

SUMMARY = re.compile(r"^(\d+) passed, (\d+) skipped, (\d+) failed, (\d+) not applicable$", re.MULTILINE)


def conform(world: str, *flags: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "toyroom", "conform", "--world", world, "--timeout", "10", *flags],
        capture_output=True,
        text=True,
        timeout=300,
    )


def counts(result: subprocess.CompletedProcess[str]) -> tuple[int, int, int, int]:
    found = SUMMARY.search(result.stdout)
    assert found is not None, f"no summary line:\n{result.stdout}\n{result.stderr}"
    passed, skipped, failed, na = map(int, found.groups())
    return passed, skipped, failed, na


def test_skips_are_counted_apart_and_strict_fails_on_them(world: str) -> None:
    with EngineProcess(world, "--scenario", "paper-2"):  # the robot only observes
        plain, strict = conform(world), conform(world, "--strict")
    passed, skipped, failed, na = counts(plain)
    assert plain.returncode == 0 and failed == 0, plain.stdout
    assert skipped >= 7 and passed + skipped + na == len(CHECK_NAMES), plain.stdout
    assert "skip  robot commands: robot 'robot' only observes in this scene" in plain.stdout
    assert "n/a   realtime: the clock runs in lock-step" in plain.stdout
    assert strict.returncode == 1 and counts(strict) == (passed, skipped, failed, na), strict.stdout
    assert "--strict" in strict.stdout


def test_every_check_runs_on_a_scene_with_an_acting_robot(world: str) -> None:
    with EngineProcess(world, "--scenario", "paper-robot"):
        result = conform(world, "--strict")
    assert result.returncode == 0 and counts(result)[1:3] == (0, 0), result.stdout


def test_pick_place_give_is_skipped_when_every_item_is_held(world: str, tmp_path: Path) -> None:
    scenario = tmp_path / "held.toml"
    scenario.write_text(HELD)
    with EngineProcess(world, "--scenario", str(scenario)):
        result = conform(world)
    failures = [line for line in result.stdout.splitlines() if line.startswith("FAIL")]
    assert result.returncode == 0 and failures == [], result.stdout + result.stderr
    assert (
        "skip  pick place give: no item rests free at a location the robot can reach ('car' held by A1)"
        in result.stdout
    ), result.stdout
