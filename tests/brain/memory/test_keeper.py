"""The node's side of the memory (:class:`brain.memory.MemoryKeeper`): the day a day starts
from, said in the log, and a day cut short (its brain stopped before the day's end, its
checkpoint kept) never skipped in silence."""

from __future__ import annotations

import logging
from pathlib import Path

import msgspec
import pytest

from brain.memory import MemoryKeeper, open_memory
from protocol import Household, Scene
from tests.brain.memory.test_store import snapshot
from tests.scenes import household_scene


def day_of(day: int) -> Scene:
    return msgspec.structs.replace(household_scene(), household=Household(id="home", day=day))


def started(path: Path, day: int, caplog: pytest.LogCaptureFixture) -> tuple[int | None, bool | None, str]:
    """Day ``day`` of ``home`` started at its first tick: the day and kind it starts from,
    and the warnings logged."""
    caplog.clear()
    with open_memory(path) as store, caplog.at_level(logging.INFO, logger="toyroom.brain"):
        memory = MemoryKeeper(store).start(day_of(day), 0)
    warnings = "\n".join(r.getMessage() for r in caplog.records if r.levelno >= logging.WARNING)
    return (None, None, warnings) if memory is None else (memory.day, memory.final, warnings)


def test_a_day_after_one_cut_short_starts_from_its_checkpoint_and_says_so(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    path = tmp_path / "memory.sqlite"
    with open_memory(path) as store:
        store.save(snapshot(1))
        store.save(snapshot(2, final=False, tick=800))  # day 2's brain killed after tick 800
    day, final, warned = started(path, 3, caplog)
    assert (day, final) == (2, False), (
        f"expected day 3 to start from day 2's checkpoint, got day {day} {final}"
    )
    expected = "household 'home' day 3: day 2 has no end (its brain stopped at or after tick 800"
    assert expected in warned, f"expected a warning {expected!r}, got {warned!r}"


def test_a_day_after_a_whole_day_starts_from_its_end_without_a_warning(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    path = tmp_path / "memory.sqlite"
    with open_memory(path) as store:
        store.save(snapshot(1))
        store.save(snapshot(2))
    assert started(path, 3, caplog) == (2, True, ""), "expected day 2's end and no warning"


def test_days_not_remembered_are_named(tmp_path: Path, caplog: pytest.LogCaptureFixture) -> None:
    path = tmp_path / "memory.sqlite"
    with open_memory(path) as store:
        store.save(snapshot(1))
    day, final, warned = started(path, 4, caplog)
    assert (day, final) == (1, True), (day, final)
    assert "household 'home' day 4: days 2 and 3 are not remembered" in warned, warned
