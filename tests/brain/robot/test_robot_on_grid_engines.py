"""The acting robot on the grid engines: ``toyroom run --engine grid`` (the Python example)
and ``--engine csharp`` (the C# SDK's sample under Mono) finish the robot scenarios as
sim2d does. Both hear a ``say`` within the protocol's earshot (the same region, or within 2
cells) and start a command's work on the tick it turns ``running``; before, a tick lost
there let A1 walk 3 cells into S1 and the robot's say failed ``out of earshot: A1``."""

from __future__ import annotations

import json
from pathlib import Path

import pytest
from support import EventsCsv, toyroom_run

ROOT = Path(__file__).resolve().parents[3]


def final_agents(trace: Path) -> dict[str, dict]:
    """The agents of the last engine state in a trace, by id."""
    last = None
    for line in trace.read_text().splitlines():
        record = json.loads(line)
        if record["key"].endswith("/engine/state"):
            last = record["payload"]
    assert last is not None, f"no engine state in {trace}"
    return {a["id"]: a for a in last["agents"]}


@pytest.mark.parametrize("engine", ["grid", "csharp"])
def test_paper_robot_finishes_on_the_grid_engines(engine: str, tmp_path: Path) -> None:
    out = toyroom_run(tmp_path / "out", "paper-robot", "--engine", engine)
    events = EventsCsv(out / "events.csv")
    failed = events.find(actor="robot", kind="command", detail__contains="failed")
    assert not failed, f"{engine}: robot commands failed: {failed}"
    said = events.find(actor="robot", kind="command", detail__contains=" say ")
    assert said and said[-1]["detail"].endswith("say succeeded"), f"{engine}: the say: {said}"
    told = events.first_tick(actor="robot", kind="say", item="skate", target="A1", detail="occupied by A2")
    yes = events.first_tick(actor="A2", kind="reply", item="skate", detail="yes")
    skate = events.first_tick(actor="robot", kind="give", item="skate", target="A1")
    ball = events.first_tick(actor="robot", kind="give", item="ball", target="A2")
    assert told < yes < skate < ball, (told, yes, skate, ball)
    agents = final_agents(out / "trace.jsonl")
    assert agents["A1"]["holding"] == "skate" and agents["A1"]["activity"] == "playing", agents["A1"]
    assert agents["A2"]["holding"] == "ball" and agents["A2"]["activity"] == "playing", agents["A2"]


def test_paper_robot_decline_tells_a1_where_the_ball_is_on_the_grid_engine(tmp_path: Path) -> None:
    out = toyroom_run(tmp_path / "out", "paper-robot-decline", "--engine", "grid")
    events = EventsCsv(out / "events.csv")
    assert not events.find(actor="robot", kind="command", detail__contains="failed")
    no = events.first_tick(actor="A2", kind="reply", item="skate", detail="no")
    assert events.first_tick(actor="robot", kind="say", item="ball", target="A1", location="S1") > no


def test_the_protocol_states_the_earshot_rule_in_the_say_row() -> None:
    text = (ROOT / "protocol" / "README.md").read_text(encoding="utf-8")
    row = next(line for line in text.splitlines() if line.startswith("| `say` |"))
    assert "same region" in row or "robot's region" in row, row
    assert "2 cells" in row, row
    assert "engine's choice" not in text, "earshot is the protocol's rule, not each engine's"
