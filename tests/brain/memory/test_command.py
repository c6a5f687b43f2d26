"""``toyroom memory`` (``python -m brain memory``) as a user calls it: run in-process with the
program name ``toyroom`` gives it, each refusal one line begun ``toyroom memory:``, exit 2, and
the memory file left as it was."""

from __future__ import annotations

import hashlib
from collections.abc import Callable
from pathlib import Path

import pytest

from brain.__main__ import main
from brain.errors import MemoryFileError
from brain.memory import PersonMemory, Snapshot, open_memory
from bridge.flags import PROG_ENV
from tests.brain.memory.test_store import snapshot

PREFIX = "toyroom memory: "


def memory(
    args: list[str], capsys: pytest.CaptureFixture[str], monkeypatch: pytest.MonkeyPatch
) -> tuple[int, str, str]:
    """``toyroom memory ARGS``: its exit status, standard output and standard error."""
    capsys.readouterr()
    monkeypatch.setenv(PROG_ENV, "toyroom memory")  # as toyroom's exec of the node sets it
    code = main(["memory", *args])
    out, err = capsys.readouterr()
    return code, out, err


def refused(result: tuple[int, str, str], *words: str) -> str:
    """The one error line of a refusal, checked to name each of ``words``."""
    code, out, err = result
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1, f"expected one error line and exit 2, got {code}: {err!r} {out!r}"
    assert lines[0].startswith(PREFIX), f"expected the line to begin {PREFIX!r}, got {lines[0]!r}"
    missing = [w for w in words if w not in lines[0]]
    assert not missing, f"expected the line to name {missing}, got {lines[0]!r}"
    return lines[0]


def two_households(tmp_path: Path) -> Path:
    """A memory of households ``home`` and ``other``, each with its own A1 and A2."""
    path = tmp_path / "mem.sqlite"
    with open_memory(path) as store:
        store.save(snapshot(1))
        store.save(snapshot(1, household="other"))
    return path


def digest(path: Path) -> str:
    return hashlib.sha256(path.read_bytes()).hexdigest()


def test_export_never_overwrites_the_memory(tmp_path: Path, capsys, monkeypatch) -> None:
    path = two_households(tmp_path)
    before = digest(path)
    refused(memory(["export", str(path), "--out", str(path)], capsys, monkeypatch), "memory file itself")
    alias = tmp_path / "sub" / ".." / "mem.sqlite"
    (tmp_path / "sub").mkdir()
    refused(memory(["export", str(path), "--out", str(alias)], capsys, monkeypatch), "memory file itself")
    (tmp_path / "link.sqlite").symlink_to(path)
    refused(memory(["export", str(path), "--out", str(tmp_path / "link.sqlite")], capsys, monkeypatch))
    other = tmp_path / "other.sqlite"
    open_memory(other).close()
    kept = digest(other)
    refused(memory(["export", str(path), "--out", str(other)], capsys, monkeypatch), "SQLite file")
    assert digest(path) == before and digest(other) == kept, "expected both memory files unchanged"
    code, out, _ = memory(["export", str(path), "--out", str(tmp_path / "mem.json")], capsys, monkeypatch)
    assert code == 0 and '"household": "other"' in (tmp_path / "mem.json").read_text(), out


def test_export_to_a_missing_folder_or_to_a_folder_is_one_line(tmp_path: Path, capsys, monkeypatch) -> None:
    path = two_households(tmp_path)
    missing = tmp_path / "nowhere" / "mem.json"
    refused(memory(["export", str(path), "--out", str(missing)], capsys, monkeypatch), str(missing.parent))
    refused(memory(["export", str(path), "--out", str(tmp_path)], capsys, monkeypatch), "is a folder")


def test_forget_in_one_household_of_two(tmp_path: Path, capsys, monkeypatch) -> None:
    path = two_households(tmp_path)
    refused(
        memory(["forget", str(path), "A1"], capsys, monkeypatch),
        "2 households",
        "home",
        "other",
        "--household",
    )
    with open_memory(path) as store:
        assert store.people_by_household() == {"home": ["A1", "A2"], "other": ["A1", "A2"]}, (
            "expected an ambiguous forget to remove nothing"
        )
    code, out, err = memory(["forget", str(path), "A1", "--household", "other"], capsys, monkeypatch)
    assert code == 0 and "5 rows removed" in out, (
        f"expected A1's 5 rows in 'other' removed, got {code}: {out}{err}"
    )
    with open_memory(path) as store:
        held = store.people_by_household()
    assert held == {"home": ["A1", "A2"], "other": ["A2"]}, f"expected A1 kept in 'home' only, got {held}"
    refused(memory(["forget", str(path), "A1", "--household", "nope"], capsys, monkeypatch), "'nope'", "home")
    refused(memory(["forget", str(path), "A1", "--household", "other"], capsys, monkeypatch), "'A1'", "A2")


@pytest.mark.parametrize("name", ["Bob", "a1", " A1", ""])
def test_forget_of_a_name_the_file_does_not_hold_is_an_error(
    name: str, tmp_path: Path, capsys, monkeypatch
) -> None:
    path = two_households(tmp_path)
    before = digest(path)
    refused(memory(["forget", str(path), name], capsys, monkeypatch), repr(name), "A1, A2")
    assert digest(path) == before, "expected the file unchanged"


def test_forget_removes_the_persons_bytes_from_the_file(tmp_path: Path) -> None:
    """As a SQLite build whose ``secure_delete`` is off by default would: the freed pages
    must not keep the person's name."""
    path = tmp_path / "mem.sqlite"
    with open_memory(path) as store:
        for day in range(1, 30):
            people = (*snapshot(day).people, PersonMemory("Zelda-Forgotten", {"ball": 1.0}, {}))
            store.save(Snapshot("home", day, 100, True, people, {}))
        store._db.execute("PRAGMA secure_delete = 0")  # the build's default, off
        assert path.read_bytes().count(b"Zelda-Forgotten") > 0
        assert store.forget("Zelda-Forgotten") == 29
        left = copies(tmp_path, b"Zelda-Forgotten")
        assert not any(left.values()), f"expected no copy of the forgotten name, file open, found {left}"
    left = copies(tmp_path, b"Zelda-Forgotten")
    assert not any(left.values()), f"expected no copy of the forgotten name on disk, found {left}"


def copies(folder: Path, name: bytes) -> dict[str, int]:
    """How many times each file of the memory (its journal and WAL too) holds ``name``."""
    return {p.name: p.read_bytes().count(name) for p in folder.iterdir() if p.name.startswith("mem.sqlite")}


def test_a_read_only_memory_is_refused_at_open(
    tmp_path: Path, capsys, monkeypatch, read_only: Callable[[Path], None]
) -> None:
    path = two_households(tmp_path)
    read_only(path)
    with pytest.raises(MemoryFileError, match=f"memory file {path} cannot be written"):
        open_memory(path)
    refused(
        memory(["forget", str(path), "A1", "--household", "home"], capsys, monkeypatch), "cannot be written"
    )
    code, out, _ = memory(["show", str(path)], capsys, monkeypatch)
    assert code == 0 and "A1" in out, "expected show to read a read-only file"


def test_show_writes_nothing_and_names_what_it_was_given(tmp_path: Path, capsys, monkeypatch) -> None:
    empty = tmp_path / "empty.sqlite"
    empty.touch()
    refused(memory(["show", str(empty)], capsys, monkeypatch), "empty (0 bytes)")
    refused(memory(["export", str(empty)], capsys, monkeypatch), "empty (0 bytes)")
    assert empty.stat().st_size == 0, (
        f"expected show to write nothing, the file has {empty.stat().st_size} bytes"
    )
    refused(memory(["show", str(tmp_path)], capsys, monkeypatch), "is a folder")
    refused(memory(["show", str(tmp_path / "none.sqlite")], capsys, monkeypatch), "no memory file")
    path = two_households(tmp_path)
    before = (digest(path), path.stat().st_mtime_ns)
    code, out, _ = memory(["show", str(path)], capsys, monkeypatch)
    assert code == 0 and "other" in out, out
    assert (digest(path), path.stat().st_mtime_ns) == before, "expected show to leave the file untouched"
