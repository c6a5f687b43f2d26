"""Every time setting has a stated floor, refused before anything starts in one line (exit 2)
(issue 64, item 8): ``decision_seconds=1e-9`` used to be accepted, and its run reached tick 5
in 170 s against 306 ticks in 4 s at the default. The brain's settings (``python -m brain
check-settings`` before any node), a scenario's ``tick_seconds`` (sim2d's loader, before any
node), and the command line's ``--timeout``, ``--wait-subscribers`` and ``--ping``; each floor
is in ``docs/usage.md``'s limits table. Real ``toyroom`` processes."""

from __future__ import annotations

import re
import subprocess
import sys
from pathlib import Path

import pytest

from brain.robotsettings import MIN_COMMAND_TIMEOUT, MIN_DECISION_SECONDS
from brain.settings import ModelSettings, RobotSettings
from sim2d.scenario.scenario import MIN_TICK_SECONDS, load_scenario
from toyroom.cli.floors import MIN_REQUEST_TIMEOUT

ROOT = Path(__file__).resolve().parents[3]
SCENARIOS = ROOT / "sim2d" / "scenarios"
RUN = ("run", "--scenario", "sally-anne", "--no-live", "--out", "{tmp}/r")

CASES = [
    ((*RUN, "--set", "decision_seconds=1e-9"), "decision_seconds=1e-09 (allowed: decision_seconds >= 0.05 s"),
    (
        ("eval", "--episodes", "1", "--set", "decision_seconds=0.01", "--out", "{tmp}/e"),
        "decision_seconds=0.01 (allowed: decision_seconds >= 0.05 s",
    ),
    ((*RUN, "--set", "navigate_timeout=1e-9"), "navigate_timeout=1e-09 (allowed: navigate_timeout >= 1"),
    ((*RUN, "--set", "action_timeout=0.5"), "action_timeout=0.5 (allowed: action_timeout >= 1"),
    ((*RUN, "--set", "answer_timeout=0.001"), "answer_timeout=0.001 (allowed: answer_timeout >= 1"),
    (
        ("run", "--scenario", "{tmp}/tiny-tick.toml", "--no-live", "--out", "{tmp}/r"),
        "tick_seconds must be a finite number from 0.01 and at most 3600",
    ),
    (
        ("export-scenario", "--scenario", "{tmp}/tiny-tick.toml", "--out", "{tmp}/s.json"),
        "tick_seconds must be a finite number from 0.01",
    ),
    ((*RUN, "--timeout", "1e-9"), "toyroom run: --timeout 1e-09: expected 0 (no limit) or at least 1 s"),
    ((*RUN, "--timeout", "nan"), "toyroom run: --timeout nan: expected 0 (no limit) or at least 1 s"),
    (("conform", "--timeout", "0"), "toyroom conform: --timeout 0: expected at least 1 s"),
    (
        ("replay", "{tmp}/run.mcap", "--wait-subscribers", "-1"),
        "toyroom replay: --wait-subscribers -1.0: expected a number of seconds >= 0",
    ),
    (("gateway", "--ping", "0.001"), "toyroom gateway: --ping must be at least 0.1 s"),
]


def _tiny_tick(folder: Path) -> None:
    """sally-anne with a tick of 1e-9 s (its map beside it)."""
    (folder / "sally-anne.map.toml").write_text((SCENARIOS / "sally-anne.map.toml").read_text())
    text = (SCENARIOS / "sally-anne.toml").read_text()
    assert "tick_seconds = 0.1" in text, "sally-anne's tick changed: update this test"
    (folder / "tiny-tick.toml").write_text(text.replace("tick_seconds = 0.1", "tick_seconds = 1e-9"))


@pytest.mark.parametrize(
    ("argv", "expected"), CASES, ids=lambda c: " ".join(c) if isinstance(c, tuple) else ""
)
def test_a_time_below_its_floor_is_one_line_and_exit_2_before_anything_starts(
    tmp_path: Path, argv: tuple[str, ...], expected: str
) -> None:
    _tiny_tick(tmp_path)
    before = sorted(p.name for p in tmp_path.iterdir())
    args = [a.format(tmp=tmp_path) for a in argv]
    result = subprocess.run(
        [sys.executable, "-m", "toyroom", *args], capture_output=True, text=True, timeout=120
    )
    lines = result.stderr.strip().splitlines()
    assert result.returncode == 2 and len(lines) == 1 and expected in lines[0], (
        f"expected exit 2 and one line with {expected!r}, got exit {result.returncode} and:\n{result.stderr}"
    )
    after = sorted(p.name for p in tmp_path.iterdir())
    assert after == before, f"a refused command wrote something: {sorted(set(after) - set(before))}"


def test_each_floor_is_allowed_and_below_it_is_not(tmp_path: Path) -> None:
    ModelSettings(decision_seconds=MIN_DECISION_SECONDS)
    RobotSettings(navigate_timeout=MIN_COMMAND_TIMEOUT, action_timeout=1.0, answer_timeout=1.0)
    with pytest.raises(ValueError, match="decision_seconds"):
        ModelSettings(decision_seconds=MIN_DECISION_SECONDS * 0.99)
    with pytest.raises(ValueError, match="answer_timeout"):
        RobotSettings(answer_timeout=MIN_COMMAND_TIMEOUT * 0.99)
    (tmp_path / "sally-anne.map.toml").write_text((SCENARIOS / "sally-anne.map.toml").read_text())
    text = (SCENARIOS / "sally-anne.toml").read_text()
    (tmp_path / "fine.toml").write_text(
        text.replace("tick_seconds = 0.1", f"tick_seconds = {MIN_TICK_SECONDS}")
    )
    assert load_scenario(str(tmp_path / "fine.toml")).tick_seconds == MIN_TICK_SECONDS


def test_the_limits_table_states_every_time_floor() -> None:
    """docs/usage.md's limits table names each time setting with its floor."""
    text = (ROOT / "docs" / "usage.md").read_text()
    table = text[text.index("## Limits") : text.index("## Faults and bad input")]
    floors = {
        "decision_seconds": MIN_DECISION_SECONDS,
        "navigate_timeout": MIN_COMMAND_TIMEOUT,
        "action_timeout": MIN_COMMAND_TIMEOUT,
        "answer_timeout": MIN_COMMAND_TIMEOUT,
        "tick_seconds": MIN_TICK_SECONDS,
        "--timeout": MIN_REQUEST_TIMEOUT,
        "--ping": 0.1,
        "--lease-ms": 100,
    }
    rows = [line for line in table.splitlines() if line.startswith("|")]
    for name, floor in floors.items():
        named = re.compile(rf"`(?:[^`]* )?{re.escape(name)}`")  # `--timeout`, `toyroom run --timeout`
        row = next((r for r in rows if named.search(r)), None)
        assert row is not None, f"expected a row of the limits table naming `{name}`, found none"
        assert re.search(rf"\b{re.escape(f'{floor:g}')}\b", row), (
            f"expected `{name}`'s row to state its floor {floor:g}, got: {row}"
        )
    for name in ("confirm_seconds", "ask_again_after", "--wait-subscribers"):
        named = re.compile(rf"`(?:[^`]* )?{re.escape(name)}`")
        assert any(named.search(r) for r in rows), f"expected the limits table to state `{name}`'s floor"
