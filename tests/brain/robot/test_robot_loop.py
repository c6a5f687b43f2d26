"""The closed loop: engine and brain processes over loopback Zenoh; what the robot did,
read from ``events.csv``. Nothing in the brain knows these scenarios: it acts on what it
infers."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

from support import EventsCsv, toyroom_run


def final_state(trace: Path) -> dict:
    last = None
    for line in trace.read_text().splitlines():
        record = json.loads(line)
        if record["key"].endswith("/engine/state"):
            last = record["payload"]
    assert last is not None
    return last


def robot_home(trace: Path) -> tuple[int, int]:
    info = json.loads(trace.read_text().splitlines()[0])["payload"]
    robot = next(a for a in info["scene"]["agents"] if a["kind"] == "robot")
    return robot["home"]["col"], robot["home"]["row"]


def robot_ends_at_home(out: Path) -> None:
    state = final_state(out / "trace.jsonl")
    robot = next(a for a in state["agents"] if a["id"] == "robot")
    home = robot_home(out / "trace.jsonl")
    assert (robot["cell"]["col"], robot["cell"]["row"]) == home, (
        f"the robot ended at {robot['cell']}, home is {home}"
    )


def test_paper_robot_swaps_the_toys(tmp_path: Path) -> None:
    out = toyroom_run(tmp_path, "paper-robot")
    events = EventsCsv(out / "events.csv")
    told = events.first_tick(actor="robot", kind="say", item="skate", target="A1", detail="occupied by A2")
    asked = events.first_tick(actor="robot", kind="request", item="skate", target="A2")
    yes = events.first_tick(actor="A2", kind="reply", item="skate", detail="yes")
    skate = events.first_tick(actor="robot", kind="give", item="skate", target="A1")
    ball = events.first_tick(actor="robot", kind="give", item="ball", target="A2")
    assert told < asked <= yes < skate < ball, (told, asked, yes, skate, ball)
    assert any(int(r["tick"]) > skate for r in events.find(actor="A1", kind="play", item="skate"))
    assert any(int(r["tick"]) > ball for r in events.find(actor="A2", kind="play", item="ball"))
    robot_ends_at_home(out)
    state = final_state(out / "trace.jsonl")
    agents = {a["id"]: a for a in state["agents"]}
    assert agents["A1"]["holding"] == "skate" and agents["A1"]["activity"] == "playing"
    assert agents["A2"]["holding"] == "ball" and agents["A2"]["activity"] == "playing"
    first = min(int(r["tick"]) for r in events.find(actor="robot", kind="command"))
    assert first > told - 60, (
        f"the robot's first command came at tick {first}, long before the swap's task "
        f"({told}): a blip of the online estimates (A1 leaving at tick 56) started a task"
    )


def test_paper_robot_decline(tmp_path: Path) -> None:
    out = toyroom_run(tmp_path, "paper-robot-decline")
    events = EventsCsv(out / "events.csv")
    no = events.first_tick(actor="A2", kind="reply", item="skate", detail="no")
    assert not events.find(kind="give", item="skate"), "the robot must not take the skate after a no"
    assert not events.find(actor="robot", kind="take", item="skate")
    told = events.first_tick(actor="robot", kind="say", item="ball", target="A1")
    assert told > no
    assert events.find(actor="robot", kind="say", item="ball", target="A1")[0]["location"] == "S1"
    robot_ends_at_home(out)


def test_paper_tidy_puts_the_ball_back_before_a1_returns(tmp_path: Path) -> None:
    out = toyroom_run(tmp_path, "paper-tidy")
    events = EventsCsv(out / "events.csv")
    moved = events.first_tick(actor="A2", kind="drop", item="ball", location="S1")
    picked = events.first_tick(actor="robot", kind="take", item="ball", location="S1")
    placed = events.first_tick(actor="robot", kind="drop", item="ball", location="S2")
    back = events.first_tick(actor="A1", kind="waypoint", detail="5")
    assert moved < picked < placed < back, (moved, picked, placed, back)
    assert events.first_tick(actor="A1", kind="take", item="ball", location="S2") > back, (
        "A1 finds the ball in S2"
    )
    task = "put back: put the ball back at S2, where A1 left it"
    begun = events.first_tick(actor="robot", kind="task", detail=f"begin {task}")
    done = events.first_tick(actor="robot", kind="task", detail=f"done {task}")
    assert begun <= picked and placed <= done, (begun, picked, placed, done)
    robot_ends_at_home(out)


def test_tidy_policy_puts_back_what_was_moved_and_says_nothing(tmp_path: Path) -> None:
    """``policy = tidy`` (no theory of mind): the ball A2 moved from S2 to S1 goes back."""
    out = toyroom_run(tmp_path, "paper-tidy", "--set", "policy=tidy")
    events = EventsCsv(out / "events.csv")
    moved = events.first_tick(actor="A2", kind="drop", item="ball", location="S1")
    placed = events.first_tick(actor="robot", kind="drop", item="ball", location="S2")
    assert moved < placed, (moved, placed)
    assert not events.find(actor="robot", kind="say"), "tidying says nothing"


def test_announce_policy_tells_the_others_of_every_move(tmp_path: Path) -> None:
    """``policy = announce`` (no theory of mind): A2 moved the ball, so A1 is told where it is
    now, and the robot moves nothing."""
    out = toyroom_run(tmp_path, "paper-tidy", "--set", "policy=announce")
    events = EventsCsv(out / "events.csv")
    moved = events.first_tick(actor="A2", kind="drop", item="ball", location="S1")
    told = events.first_tick(actor="robot", kind="say", item="ball", target="A1", location="S1")
    assert moved < told, (moved, told)
    assert not events.find(actor="robot", kind="take"), "announcing moves no item"
    assert not events.find(actor="robot", kind="say", target="A2"), "the mover is not told"


def test_a_likely_deception_is_told_to_the_deceived_not_put_back(tmp_path: Path) -> None:
    """``paper-deceive``: A2 moves the ball A1 wants while A1 is in P1, believing A1 did not
    see (nested beliefs). The robot reads a likely deception and tells A1. With
    ``--set on_deception=put_back`` it would put the ball back behind A2's back instead, but
    not here: the ball now lies where A1 plays with it (P2), so carrying it back to S2 would
    lengthen A1's way (issue 65: a put-back must serve its owner better than leaving it)."""
    told = EventsCsv(toyroom_run(tmp_path / "tell", "paper-deceive") / "events.csv")
    moved = told.first_tick(actor="A2", kind="drop", item="ball", location="P2")
    read = told.first_tick(actor="A2", kind="deception", item="ball", target="A1")
    said = told.first_tick(actor="robot", kind="say", item="ball", target="A1", location="P2")
    assert moved <= read < said, (moved, read, said)
    assert not told.find(actor="robot", kind="take"), "the robot moves nothing behind A2's back"
    assert told.find(actor="A1", kind="play", item="ball", location="P2"), "told, A1 plays with the ball"
    back = EventsCsv(
        toyroom_run(tmp_path / "put", "paper-deceive", "--set", "on_deception=put_back") / "events.csv"
    )
    assert back.first_tick(actor="A2", kind="deception", item="ball", target="A1") == read
    taken = back.find(actor="robot", kind="take", item="ball")
    assert not taken, f"expected the ball left where A1 plays with it, got the robot taking it: {taken}"


def test_sally_anne_robot_acts_before_sally_reaches_the_basket(tmp_path: Path) -> None:
    out = toyroom_run(tmp_path, "sally-anne")
    events = EventsCsv(out / "events.csv")
    moved = events.first_tick(actor="anne", kind="drop", item="marble", location="box")
    told = events.find(actor="robot", kind="say", item="marble", target="sally")
    put_back = events.find(actor="robot", kind="drop", item="marble", location="basket")
    assert told or put_back, "the robot should tell Sally or put the marble back"
    acted = min(int(r["tick"]) for r in told + put_back)
    reached = [int(r["tick"]) for r in events.find(actor="sally", kind="take", item="marble")] or [10**9]
    assert moved < acted < reached[-1], (moved, acted, reached)
    assert events.find(actor="sally", kind="take", item="marble"), "Sally gets her marble in the end"


def test_observing_robot_does_nothing(tmp_path: Path) -> None:
    out = toyroom_run(tmp_path, "paper-robot", "--robot", "observe")
    events = EventsCsv(out / "events.csv")
    assert not events.find(kind="command"), "an observing robot sends no command"


def test_print_tree() -> None:
    result = subprocess.run(
        [sys.executable, "-m", "toyroom", "brain", "--print-tree"], capture_output=True, text=True, timeout=60
    )
    assert result.returncode == 0, result.stderr
    for node in ("inform", "swap", "put back", "go home", "ask for a swap"):
        assert node in result.stdout


def test_failing_node_fails_the_run(tmp_path: Path) -> None:
    result = subprocess.run(
        [sys.executable, "-m", "toyroom", "run", "--scenario", "no-such-scenario", "--out", str(tmp_path)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert result.returncode != 0 and "no-such-scenario" in result.stderr
