"""``toyroom memory export`` and ``import``: export -> import -> export gives the same JSON
(clock times and the scene's names included); import never writes over a memory that holds
anything; ``export --person`` holds that person only."""

from __future__ import annotations

import json
from pathlib import Path

from brain.memory import open_memory
from tests.brain.memory.test_command import digest, memory, refused, two_households
from tests.brain.memory.test_keeping import named_memory


def exported(path: Path, out: Path, capsys, monkeypatch, *extra: str) -> str:  # noqa: ANN001
    code, said, err = memory(["export", str(path), "--out", str(out), *extra], capsys, monkeypatch)
    assert code == 0, f"expected exit 0, got {code}: {err}"
    return out.read_text()


def test_export_import_export_is_the_same(tmp_path: Path, capsys, monkeypatch) -> None:
    path = named_memory(tmp_path)
    first = exported(path, tmp_path / "first.json", capsys, monkeypatch)
    again = tmp_path / "again.sqlite"
    code, out, err = memory(["import", str(again), str(tmp_path / "first.json")], capsys, monkeypatch)
    assert code == 0 and "imported 3 days" in out, f"expected 3 days imported, got {code}: {out}{err}"
    second = exported(again, tmp_path / "second.json", capsys, monkeypatch)
    assert second == first, "expected the export of the imported memory to equal the first export"
    with open_memory(again, read_only=True) as store:
        assert store.names()["home"]["A"] == "A in Kitchen", store.names()
    empty = tmp_path / "empty.sqlite"
    empty.touch()
    code, _, err = memory(["import", str(empty), str(tmp_path / "first.json")], capsys, monkeypatch)
    assert code == 0, f"expected an empty (0-byte) file imported into, got {code}: {err}"


def test_import_never_writes_over_a_memory(tmp_path: Path, capsys, monkeypatch) -> None:
    path = two_households(tmp_path)
    source = tmp_path / "mem.json"
    exported(path, source, capsys, monkeypatch)
    before = digest(path)
    refused(
        memory(["import", str(path), str(source)], capsys, monkeypatch), "already holds households", "home"
    )
    assert digest(path) == before, "expected the memory unchanged"
    target = tmp_path / "new.sqlite"
    refused(
        memory(["import", str(target), str(tmp_path / "none.json")], capsys, monkeypatch), "no export file"
    )
    (tmp_path / "bad.json").write_text('{"schema": 2, "snapshots": [{"household": "h"}]}')
    refused(memory(["import", str(target), str(tmp_path / "bad.json")], capsys, monkeypatch), "not an export")
    (tmp_path / "newer.json").write_text('{"schema": 99, "snapshots": []}')
    refused(
        memory(["import", str(target), str(tmp_path / "newer.json")], capsys, monkeypatch), "newer toyroom"
    )


def test_export_of_one_person(tmp_path: Path, capsys, monkeypatch) -> None:
    path = two_households(tmp_path)
    text = exported(path, tmp_path / "a1.json", capsys, monkeypatch, "--person", "A1", "--household", "other")
    data = json.loads(text)
    people = {(s["household"], p["person"]) for s in data["snapshots"] for p in s["people"]}
    assert data["person"] == "A1" and people == {("other", "A1")}, (
        f"expected A1 of 'other' only, got {people}"
    )
    assert all(s["items"] == {} for s in data["snapshots"]), "expected none of the robot's own item knowledge"
    both = json.loads(exported(path, tmp_path / "both.json", capsys, monkeypatch, "--person", "A1"))
    assert {s["household"] for s in both["snapshots"]} == {"home", "other"}, both
    refused(
        memory(["import", str(tmp_path / "n.sqlite"), str(tmp_path / "a1.json")], capsys, monkeypatch),
        "holds one person only",
    )
    refused(memory(["export", str(path), "--person", "Bob"], capsys, monkeypatch), "no person 'Bob'")
    refused(memory(["export", str(path), "--household", "home"], capsys, monkeypatch), "give --person too")
