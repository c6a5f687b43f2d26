"""What a memory file keeps, and for how long: each day with its clock time; history older
than ``keep_days`` pruned at the next save, each household's latest day kept whatever its age;
an older file's days given the upgrade's time; and ``toyroom memory show --person --household
--latest``, places and items named as the scene names them."""

from __future__ import annotations

import sqlite3
import time
from pathlib import Path

import msgspec

from brain.__main__ import run_parser
from brain.memory import KEEP_DAYS, MemoryKeeper, PersonMemory, Snapshot, open_memory
from brain.memory.opening import APPLICATION_ID, MIGRATIONS
from protocol import Household
from tests.brain.memory.test_command import memory, refused
from tests.brain.memory.test_store import snapshot
from tests.scenes import household_scene

DAY = 86400.0


def test_history_older_than_keep_days_goes_at_the_next_save(tmp_path: Path) -> None:
    path = tmp_path / "memory.sqlite"
    now = [1_000_000.0]
    with open_memory(path, keep_days=2) as store:
        store.clock = lambda: now[0]
        store.save(snapshot(1, household="other"))  # another household's only day: its latest
        for day, at in ((1, 0.0), (2, 1.0), (3, 1.5)):
            now[0] = 1_000_000.0 + at * DAY
            store.save(snapshot(day))
        held = {(s.household, s.day): t for s, t in store.saved()}
        assert held == {
            ("home", 1): 1_000_000.0,
            ("home", 2): 1_000_000.0 + DAY,
            ("home", 3): 1_000_000.0 + 1.5 * DAY,
            ("other", 1): 1_000_000.0,
        }, f"expected each day with its clock time, nothing pruned yet, got {held}"
        now[0] = 1_000_000.0 + 3.2 * DAY
        store.save(snapshot(4))
        kept = sorted((s.household, s.day) for s in store.snapshots())
        assert kept == [("home", 3), ("home", 4), ("other", 1)], (
            f"expected days saved over 2 days ago pruned but each household's latest, got {kept}"
        )
        store.keep_days = 0
        store.save(snapshot(5))
        kept = sorted((s.household, s.day) for s in store.snapshots())
        assert kept == [("home", 5), ("other", 1)], f"expected only what tomorrow needs, got {kept}"
        assert store.morning("home", 6) == snapshot(5), "expected tomorrow to start from day 5"


def test_the_default_keeps_a_stated_number_of_days(tmp_path: Path) -> None:
    assert KEEP_DAYS == 30, f"expected the documented default of 30 days, got {KEEP_DAYS}"
    assert run_parser().parse_args(["--memory", "m.sqlite"]).keep_days == KEEP_DAYS
    assert run_parser().parse_args(["--keep-days", "7"]).keep_days == 7


def test_an_older_file_is_given_clock_times_and_names(tmp_path: Path) -> None:
    path = tmp_path / "memory.sqlite"
    with sqlite3.connect(path) as db:  # a schema-1 file, as the toyroom before wrote it
        db.executescript(MIGRATIONS[0])
        db.execute("INSERT INTO days VALUES ('home', 1, 1, 100)")
        db.execute(f"PRAGMA application_id = {APPLICATION_ID}")
        db.execute("PRAGMA user_version = 1")
    before = time.time()
    with open_memory(path) as store:
        ((_, saved_at),) = store.saved()
        assert before - 5 <= saved_at <= time.time() + 5, f"expected the upgrade's time, got {saved_at}"
        assert store.names() == {}


def named_memory(tmp_path: Path) -> Path:
    """Days 1 and 2 of ``home`` (and day 1 of ``other``), with the names of ``home``'s scene:
    room R1 is the "Kitchen", the ball the "red ball"."""
    path = tmp_path / "memory.sqlite"
    scene = household_scene()
    regions = tuple(msgspec.structs.replace(r, name="Kitchen") if r.id == "R1" else r for r in scene.regions)
    items = tuple(msgspec.structs.replace(i, name="red ball") if i.id == "ball" else i for i in scene.items)
    scene = msgspec.structs.replace(
        scene, regions=regions, items=items, household=Household(id="home", day=1)
    )
    a1 = PersonMemory("A1", {"ball": 0.8, "out": 0.2}, {"ball": {"A": 0.9, "B": 0.1}})
    a2 = PersonMemory("A2", {"skate": 0.8, "out": 0.2}, {"skate": {"B": 1.0}})
    with open_memory(path) as store:
        MemoryKeeper(store).start(scene, 0)  # keeps the scene's names
        store.save(Snapshot("home", 1, 500, True, (a1, a2), {}))
        store.save(Snapshot("home", 2, 700, True, (a1, a2), {}))
        store.save(snapshot(1, household="other"))
    return path


def test_show_one_person_of_one_household_latest_day_with_the_scenes_names(
    tmp_path: Path, capsys, monkeypatch
) -> None:
    path = named_memory(tmp_path)
    with open_memory(path, read_only=True) as store:
        names = store.names()["home"]
    assert names == {"A": "A in Kitchen", "B": "B in R2", "ball": "red ball (ball)"}, (
        f"expected places named with their rooms, and the ball's name, got {names}"
    )
    args = ["show", str(path), "--person", "A1", "--household", "home", "--latest"]
    code, out, err = memory(args, capsys, monkeypatch)
    assert code == 0, f"expected exit 0, got {code}: {err}"
    rows = [line for line in out.splitlines() if " home " in line or "│ home" in line]
    assert len(rows) == 1 and "700" in rows[0], f"expected one row, day 2 (tick 700), got {rows}"
    assert "A2" not in out and "other" not in out.replace("memory", ""), f"expected A1 of home only: {out}"
    flat = " ".join(out.split())
    assert "red ball (ball) at A in Kitchen 0.90" in flat and "red ball (ball) 0.80" in flat, (
        f"expected the belief and favourite as the scene names them, got {out}"
    )
    code, out, _ = memory(["show", str(path), "--household", "other"], capsys, monkeypatch)
    assert code == 0 and "A2" in out and "│ home" not in out, out
    refused(memory(["show", str(path), "--person", "Bob"], capsys, monkeypatch), "no person 'Bob'", "A1, A2")
    refused(memory(["show", str(path), "--household", "nope"], capsys, monkeypatch), "no household 'nope'")
