"""The memory file: one transaction per save, the day a day starts from, forgetting a person,
and the files it refuses (never read as an empty memory)."""

from __future__ import annotations

import sqlite3
from pathlib import Path

import pytest

from brain.errors import MemoryFileError, MemoryRequestError
from brain.memory import SCHEMA_VERSION, PersonMemory, Snapshot, open_memory
from brain.memory.transfer import export


def snapshot(day: int, final: bool = True, tick: int = 100, household: str = "home") -> Snapshot:
    people = (
        PersonMemory("A1", {"ball": 0.8, "skate": 0.1, "out": 0.1}, {"ball": {"S1": 0.9, "P2": 0.1}}),
        PersonMemory("A2", {"ball": 0.2, "skate": 0.7, "out": 0.1}, {"skate": {"P1": 1.0}}),
    )
    return Snapshot(household, day, tick, final, people, {"ball": {"S1": 1.0}, "skate": {"P1": 1.0}})


def test_a_day_starts_from_the_last_days_end_and_a_restart_from_its_checkpoint(tmp_path: Path) -> None:
    path = tmp_path / "memory.sqlite"
    with open_memory(path) as memory:
        assert memory.morning("home", 1) is None, "day 1 of a new household starts from nothing"
        memory.save(snapshot(1))
        memory.save(snapshot(2, final=False, tick=40))
    with open_memory(path) as memory:  # reopened: everything was committed
        assert memory.morning("home", 2) == snapshot(1), "day 2 starts from day 1's end"
        cut = snapshot(2, final=False, tick=40)
        assert memory.morning("home", 3) == cut, "day 2 has no end: day 3 starts from its checkpoint"
        assert memory.resume("home", 2) == cut, "a restart resumes"
        assert memory.resume("home", 3) == cut, "no checkpoint of day 3: its morning"
        memory.save(snapshot(2, tick=900))
        assert memory.morning("home", 3) == snapshot(2, tick=900), "day 3 starts from day 2's end"
        assert memory.resume("home", 2) == snapshot(1), (
            "a day's end replaces its checkpoint: a rerun starts afresh"
        )
        assert memory.morning("elsewhere", 2) is None and memory.households() == ["home"]
        exported = export(memory)
    assert exported["schema"] == SCHEMA_VERSION and len(exported["snapshots"]) == 2, exported


def test_forget_removes_every_row_about_a_person_in_one_household(tmp_path: Path) -> None:
    path = tmp_path / "memory.sqlite"
    with open_memory(path) as memory:
        memory.save(snapshot(1))
        memory.save(snapshot(2))
        memory.save(snapshot(1, household="other"))
        removed = memory.forget("A1", "home")
        assert removed == 2 * (3 + 2), f"3 preference and 2 belief rows on each of 2 days, got {removed}"
        assert memory.people_by_household() == {"home": ["A2"], "other": ["A1", "A2"]}
        morning = memory.morning("home", 3)
        assert morning is not None and morning.person("A1") is None and morning.person("A2") is not None
        assert memory.forget("A1") == 5, "A1 is now in one household only: no need to name it"
        with pytest.raises(MemoryRequestError, match="holds no person 'A1' \\(it holds A2"):
            memory.forget("A1")


def test_a_damaged_file_is_refused_with_its_name(tmp_path: Path) -> None:
    path = tmp_path / "memory.sqlite"
    path.write_bytes(b"this is not a database, " * 200)
    with pytest.raises(MemoryFileError, match=f"memory file {path} is not a toyroom memory"):
        open_memory(path)


def test_a_truncated_memory_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "memory.sqlite"
    with open_memory(path) as memory:
        for day in range(1, 40):
            memory.save(snapshot(day))
    data = path.read_bytes()
    path.write_bytes(data[: len(data) // 2])
    with pytest.raises(MemoryFileError, match=f"memory file {path}"):
        with open_memory(path) as memory:
            memory.snapshots()


def test_another_sqlite_file_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "other.sqlite"
    with sqlite3.connect(path) as db:
        db.execute("CREATE TABLE notes (text TEXT)")
    with pytest.raises(MemoryFileError, match="another SQLite file, not a toyroom memory.*notes"):
        open_memory(path)


def test_a_newer_schema_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "memory.sqlite"
    open_memory(path).close()
    with sqlite3.connect(path) as db:
        db.execute(f"PRAGMA user_version = {SCHEMA_VERSION + 1}")
    with pytest.raises(MemoryFileError, match=f"newer toyroom \\(schema {SCHEMA_VERSION + 1}"):
        open_memory(path)


def test_a_file_held_by_another_brain_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "memory.sqlite"
    with open_memory(path):  # a new file (its schema written at open)
        with pytest.raises(MemoryFileError, match="in use by another process"):
            open_memory(path)
    with open_memory(path):  # an existing one (nothing written at open): held all the same
        with pytest.raises(MemoryFileError, match="in use by another process"):
            open_memory(path)
    open_memory(path).close()  # let go: usable again
