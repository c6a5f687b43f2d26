"""A household lived by hand: ``toyroom run --memory FILE`` for day 1, then day 2 of the same
household starts from what day 1 learned (real engine and brain processes, one file)."""

from __future__ import annotations

from pathlib import Path

from support import toyroom_run

from brain.memory import open_memory
from sim2d.scenario.maps import SCENARIO_DIR

TICKS = 150


def day(folder: Path, number: int) -> Path:
    """``paper-auto``, :data:`TICKS` ticks long, as day ``number`` of household ``h1``."""
    text = (SCENARIO_DIR / "paper-auto.toml").read_text()
    assert "max_ticks = 2000" in text, "expected paper-auto's max_ticks"
    path = folder / f"h1-day{number}.toml"
    path.write_text(
        text.replace("max_ticks = 2000", f"max_ticks = {TICKS}").replace(
            'name = "paper-auto"', f'name = "h1-day{number}"'
        )
        + f'\n[household]\nid = "h1"\nday = {number}\n'
    )
    return path


def test_toyroom_run_with_a_memory_lives_a_household_day_by_day(tmp_path: Path) -> None:
    memory = tmp_path / "h1.sqlite"
    toyroom_run(tmp_path / "day1", str(day(tmp_path, 1)), "--memory", str(memory))
    with open_memory(memory, read_only=True) as store:
        first = [(s.household, s.day, s.final) for s in store.snapshots()]
    assert first == [("h1", 1, True)], f"expected day 1's end saved, got {first}"
    out = toyroom_run(
        tmp_path / "day2", str(day(tmp_path, 2)), "--memory", str(memory), "--log-level", "INFO"
    )
    log = (out / "brain.log").read_text()
    assert "household 'h1' day 2: starting from day 1's end" in log, (
        f"expected day 2 to start from day 1's end, got:\n{log[-2000:]}"
    )
    with open_memory(memory, read_only=True) as store:
        both = [(s.household, s.day, s.final) for s in store.snapshots()]
    assert both == [("h1", 1, True), ("h1", 2, True)], f"expected days 1 and 2 saved, got {both}"
