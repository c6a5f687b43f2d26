"""``toyroom memory forget`` and the copies a memory file does not hold: named without
``--everywhere``; with ``--everywhere DIR``, the run outputs under DIR that name the person and
the household removed and listed, and nothing else (other households, other kinds of file,
anything outside DIR, through a link or not)."""

from __future__ import annotations

import json
import sqlite3
from pathlib import Path

from brain.memory import open_memory
from tests.brain.memory.test_command import memory, refused, two_households


def outputs(root: Path, outside: Path) -> dict[str, Path]:
    """Run outputs of households ``home`` and ``other`` under ``root``, as runs write them."""
    files = {
        "mind": root / "run-home" / "mind.csv",
        "report": root / "run-home" / "report.md",
        "trace": root / "run-home" / "trace.jsonl",
        "log": root / "run-home" / "minds-btom.jsonl",
        "events": root / "run-home" / "events.csv",
        "brain-log": root / "run-home" / "brain.log",
        "morning": root / "work" / "mornings" / "chain-home" / "day1.json",
        "export": root / "exports" / "mem.json",
        "other-mind": root / "run-other" / "mind.csv",
        "other-trace": root / "run-other" / "trace.jsonl",
        "scenario": root / "scenarios" / "home-day2.toml",
        "lookalike": root / "run-home2" / "mind.csv",
    }
    texts = {
        "mind": "tick,agent,preference\n0,A1,ball\n0,A2,skate\n",
        "report": "# A1 wanted the ball\n",
        "trace": json.dumps({"scene": {"household": {"id": "home", "day": 1}}, "agents": ["A1", "A2"]}),
        "log": '{"tick": 0, "agents": [{"agent": "A1"}], "household": "home"}\n',
        "events": "tick,kind,actor,item\n3,take,A1,ball\n",
        "brain-log": "brain: forgot nothing of A1 yet\n",
        "morning": json.dumps({"items": {}, "favourites": {"A1": "ball"}, "household": "home"}),
        "export": json.dumps(
            {"schema": 2, "snapshots": [{"household": "home", "people": [{"person": "A1"}]}]}
        ),
        "other-mind": "tick,agent\n0,A1\n",
        "other-trace": json.dumps({"scene": {"household": {"id": "other"}}, "agents": ["A1"]}),
        "scenario": '[[agents]]\nid = "A1"\n[household]\nid = "home"\n',
        "lookalike": "tick,agent\n0,A10\n0,xA1\n",  # another id containing A1, with home beside it
    }
    for key, path in files.items():
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(texts[key])
    (root / "run-home2" / "trace.jsonl").write_text('{"household": "home"}')
    outside.write_text("tick,agent\n0,A1\nhome\n")
    (root / "run-home" / "linked.mcap").symlink_to(outside)
    return files


def test_forget_names_the_copies_it_cannot_reach(tmp_path: Path, capsys, monkeypatch) -> None:
    path = two_households(tmp_path)
    code, out, err = memory(["forget", str(path), "A1", "--household", "home"], capsys, monkeypatch)
    assert code == 0, f"expected exit 0, got {code}: {err}"
    for where in ("mind.csv", "recordings", "mornings", "exports", "--everywhere DIR"):
        assert where in out, (
            f"expected forget to name {where!r} among the copies it cannot reach, got {out!r}"
        )


def test_forget_everywhere_removes_the_copies_of_the_person_in_that_household_only(
    tmp_path: Path, capsys, monkeypatch
) -> None:
    path = two_households(tmp_path)
    root = tmp_path / "outputs"
    outside = tmp_path / "outside-mind.csv"
    files = outputs(root, outside)
    (root / "work" / "memory").mkdir()
    two_households(root / "work" / "memory").rename(root / "work" / "memory" / "chain.sqlite")
    with sqlite3.connect(root / "foreign.sqlite") as db:
        db.execute("PRAGMA user_version = 0")
        db.execute("CREATE TABLE t (A1 TEXT)")
        db.execute("DROP TABLE t")  # an empty SQLite file: no schema, no tables
    foreign = (root / "foreign.sqlite").read_bytes()
    args = ["forget", str(path), "A1", "--household", "home", "--everywhere", str(root)]
    code, out, err = memory(args, capsys, monkeypatch)
    assert code == 0, f"expected exit 0, got {code}: {err}"
    removed = {"mind", "report", "trace", "log", "events", "brain-log", "morning", "export"}
    for key in removed:
        assert not files[key].exists(), f"expected {files[key]} removed, it is still there"
        assert f"removed {files[key]}" in out, f"expected forget to say it removed {files[key]}, got {out!r}"
    kept = set(files) - removed
    assert all(files[k].exists() for k in kept), f"expected {sorted(kept)} kept, gone: " + str(
        [k for k in kept if not files[k].exists()]
    )
    assert outside.exists() and (root / "run-home" / "linked.mcap").is_symlink(), (
        "expected nothing outside DIR touched"
    )
    assert f"left {files['other-mind']}" in out, (
        f"expected the other household's run named as left, got {out!r}"
    )
    assert f"removed 8 copies of A1 in household home under {root}" in out, out
    with open_memory(root / "work" / "memory" / "chain.sqlite", read_only=True) as store:
        held = store.people_by_household()
    assert held == {"home": ["A2"], "other": ["A1", "A2"]}, (
        f"expected A1 of home forgotten there too, got {held}"
    )
    assert "forgot A1 in " in out and "chain.sqlite (memory file): 5 rows removed" in out, out
    assert (root / "foreign.sqlite").read_bytes() == foreign, "expected another SQLite file left as it was"


def test_everywhere_must_be_a_folder(tmp_path: Path, capsys, monkeypatch) -> None:
    path = two_households(tmp_path)
    args = ["forget", str(path), "A1", "--household", "home", "--everywhere", str(tmp_path / "none")]
    refused(memory(args, capsys, monkeypatch), "--everywhere", "no such folder")
