"""The robot body: each command kind succeeds in the normal case and fails with the
right reason in each failure case (real pymunk world, engine core)."""

from __future__ import annotations

from pathlib import Path

import pytest
from support import run_command

from protocol import (
    Ask,
    Cancel,
    Cell,
    CommandState,
    CommandStatus,
    EventKind,
    Give,
    Navigate,
    Pick,
    Place,
    Request,
    RobotCommand,
    Say,
    SayTopic,
    Told,
)
from sim2d.engine import Engine
from sim2d.scenario.maps import SCENARIO_DIR

SCENARIO = f"""
name = "robot-test"
map = "{(SCENARIO_DIR / "paper.map.toml").as_posix()}"
robot = "act"
max_ticks = 5000

[[items]]
id = "ball"
shape = "ball"
at = "S1"

[[items]]
id = "skate"
shape = "board"
at = "A2"

[[agents]]
id = "A1"
kind = "person"
home = [4, 5]
wants = "skate"
script = [{{ do = "wait" }}]

[[agents]]
id = "A2"
kind = "person"
answers = "yes"
script = [{{ do = "play" }}]

[[agents]]
id = "robot"
kind = "robot"
"""


@pytest.fixture
def engine(tmp_path: Path) -> Engine:
    path = tmp_path / "robot-test.toml"
    path.write_text(SCENARIO)
    engine = Engine(str(path))
    engine.step()
    return engine


def run(engine: Engine, action: object, max_ticks: int = 400) -> list[CommandStatus]:
    """Send one command and step until it ends; every status it got, in order."""
    return run_command(engine, action, max_ticks=max_ticks)


def states(statuses: list[CommandStatus]) -> list[str]:
    return [s.state.value for s in statuses]


def test_navigate_pick_place_give_succeed(engine: Engine) -> None:
    ok = ["accepted", "running", "succeeded"]
    assert states(run(engine, Navigate(cell=Cell(5, 9)))) == ok
    assert engine.world.agents["robot"].cell == (5, 9)
    assert states(run(engine, Pick(item="ball"))) == ok
    assert engine.world.items["ball"].holder == "robot"
    assert states(run(engine, Navigate(cell=Cell(9, 9)))) == ok
    # the carried ball moved with the robot
    bx, by = engine.world.physics.position("ball")
    assert abs(bx - 9.5) < 0.2 and abs(by - 9.5) < 0.2, (bx, by)
    assert states(run(engine, Place(location="S2"))) == ok
    assert engine.world.items["ball"].location == "S2"
    assert states(run(engine, Navigate(cell=Cell(5, 10)))) == ok
    run(engine, Navigate(cell=Cell(9, 9)))
    assert states(run(engine, Pick(item="ball"))) == ok
    assert states(run(engine, Navigate(cell=Cell(4, 4)))) == ok
    assert states(run(engine, Give(person="A1"))) == ok
    assert engine.world.items["ball"].holder == "A1"


def test_a_command_for_an_unknown_robot_names_that_robot(engine: Engine) -> None:
    """Its status names the robot the command named, so it is published on that robot's key."""
    command = RobotCommand(id="boo", robot="ghost", action=Navigate(cell=Cell(5, 9)))
    statuses = engine.command(command)
    assert [(s.command, s.robot, s.state) for s in statuses] == [("boo", "ghost", CommandState.FAILED)]
    assert statuses[0].reason == "unknown robot 'ghost'; this engine's robot is 'robot'", statuses[0]


def test_failures_say_why(engine: Engine) -> None:
    def reason(action: object) -> str:
        statuses = run(engine, action)
        assert statuses[-1].state is CommandState.FAILED, f"{action} should fail, got {states(statuses)}"
        return statuses[-1].reason

    assert reason(Navigate(cell=Cell(3, 3))).startswith("not walkable: (3,3)")
    assert reason(Pick(item="kite")).startswith("unknown id 'kite': no such item")
    assert reason(Give(person="A9")).startswith("unknown id 'A9': no such person")
    assert reason(Place(location="attic")).startswith("unknown id 'attic': no such location")
    assert reason(Pick(item="ball")).startswith("item not there: 'ball' is at S1")
    assert reason(Pick(item="skate")) == "item held by A2"
    assert reason(Place(location="E")).startswith("unknown id 'E'")
    assert reason(Place(location="S1")) == "hands empty: the robot holds nothing"
    assert reason(Give(person="A1")) == "hands empty: the robot holds nothing"
    assert reason(Request(person="A2", item="skate")).startswith("out of reach: A2 is at (13,9)")
    assert reason(Request(person="A1", item="ball")) == "A1 does not hold 'ball'"
    assert reason(Say(person="A2", item="ball", topic=SayTopic.LOCATION, location="S1")).startswith(
        "out of earshot: A2 is in P2"
    )
    run(engine, Navigate(cell=Cell(5, 9)))
    run(engine, Pick(item="ball"))
    assert reason(Pick(item="ball")).startswith("hands full: the robot holds 'ball'")
    assert reason(Place(location="P2")).startswith("out of reach: location P2 is at (13,9)")
    assert reason(Give(person="A1")).startswith("out of reach: A1 is at (4,5)")


def test_unreachable_and_observe_only(tmp_path: Path) -> None:
    path = tmp_path / "observe.toml"
    path.write_text(SCENARIO.replace('robot = "act"', 'robot = "observe"'))
    engine = Engine(str(path))
    statuses = run(engine, Navigate(cell=Cell(7, 5)))
    assert states(statuses) == ["failed"] and "only observes" in statuses[0].reason


def test_swap_request_say_and_cancel(engine: Engine) -> None:
    run(engine, Navigate(cell=Cell(5, 9)))
    run(engine, Pick(item="ball"))
    said = run(engine, Say(person="A1", item="skate", topic=SayTopic.OCCUPIED, holder="A2"))
    assert said[-1].state is CommandState.FAILED and "out of earshot" in said[-1].reason
    run(engine, Navigate(cell=Cell(12, 9)))
    swap = run(engine, Request(person="A2", item="skate", offer="ball"))
    assert swap[-1].state is CommandState.SUCCEEDED and swap[-1].answer is True
    assert engine.world.agents["A2"].holding == "ball" and engine.world.agents["robot"].holding == "skate"

    # a long navigation is cancelled half-way
    command = RobotCommand(id="long", robot="robot", action=Navigate(cell=Cell(0, 10)))
    engine.command(command)
    for _ in range(5):
        engine.step()
    cancel = RobotCommand(id="stop-it", robot="robot", action=Cancel(command="long"))
    got = engine.command(cancel)
    assert [(s.command, s.state.value) for s in got] == [
        ("stop-it", "accepted"),
        ("long", "cancelled"),
        ("stop-it", "succeeded"),
    ]
    assert engine.command(RobotCommand(id="long", robot="robot", action=Pick(item="ball")))[0].reason == (
        "duplicate command id 'long'"
    )


def test_scripted_person_reacts_to_a_give(engine: Engine) -> None:
    run(engine, Navigate(cell=Cell(5, 9)))
    run(engine, Pick(item="ball"))
    run(engine, Navigate(cell=Cell(4, 4)))
    run(engine, Give(person="A1"))
    played = False
    for _ in range(300):
        result = engine.step()
        if any(e.kind is EventKind.PLAY and e.actor == "A1" and e.item == "ball" for e in result.events):
            played = True
            break
    assert played, "A1, handed the ball, should walk to a play spot and play with it"
    assert engine.world.agents["A1"].cell in [(1, 9), (13, 9)]


def test_a_failed_reset_starts_no_episode() -> None:
    from sim2d.errors import ScenarioError

    engine = Engine("paper-robot")
    first = engine.reset().state.episode
    with pytest.raises(ScenarioError):
        engine.reset("no-such-scenario")
    again = engine.reset()
    assert again.state.episode == first + 1, (
        f"episodes {first} then {again.state.episode}: a failed reset counted"
    )
    events = [e for e in (engine.step().events + engine.step().events)]
    assert all(e.episode == again.state.episode for e in events), events


def test_one_say_tells_of_several_items(engine: Engine) -> None:
    """A ``say`` with ``also`` (protocol 1.6) is one utterance: a ``say`` event per item told,
    all on the tick it succeeds; an unknown item among them fails it, naming the item."""
    run(engine, Navigate(cell=Cell(4, 6)))
    command = RobotCommand(
        id="both",
        robot="robot",
        action=Say(
            person="A1", item="ball", topic=SayTopic.LOCATION, location="S1", also=(Told("skate", "P2"),)
        ),
    )
    engine.command(command)
    events, statuses = [], []
    for _ in range(50):
        step = engine.step()
        events += [e for e in step.events if e.kind is EventKind.SAY]
        statuses += [s for s in step.statuses if s.command == "both"]
        if statuses and statuses[-1].state.final:
            break
    assert statuses[-1].state is CommandState.SUCCEEDED, statuses
    said = [(e.tick, e.target, e.item, e.location) for e in events]
    tick = said[0][0] if said else None
    assert said == [(tick, "A1", "ball", "S1"), (tick, "A1", "skate", "P2")], (
        f"expected two say events, got {said}"
    )
    wrong = Say(person="A1", item="ball", topic=SayTopic.LOCATION, location="S1", also=(Told("kite", "P2"),))
    assert run(engine, wrong)[-1].reason.startswith("unknown id 'kite': no such item")


def test_ask_gets_an_answer_in_earshot_and_fails_out_of_it(engine: Engine) -> None:
    """``ask`` (protocol 1.6): A1 (who wants the skate) answers an open question with the
    skate, a yes/no one truthfully; an ``ask`` event when asked, an ``answer`` event with the
    answer; out of earshot it fails, naming the person."""
    run(engine, Navigate(cell=Cell(12, 9)))
    far = run(engine, Ask(person="A1"))
    assert far[-1].state is CommandState.FAILED and far[-1].reason.startswith("out of earshot: A1"), far
    run(engine, Navigate(cell=Cell(4, 6)))
    events: list = []
    for question, expected in (
        (None, ("skate", True)),
        ("ball", ("ball", False)),
        ("skate", ("skate", True)),
    ):
        command = RobotCommand(id=f"ask-{question}", robot="robot", action=Ask(person="A1", item=question))
        statuses = [s for s in engine.command(command) if s.command == command.id]
        while not (statuses and statuses[-1].state.final):
            step = engine.step()
            events += [e for e in step.events if e.kind in (EventKind.ASK, EventKind.ANSWER)]
            statuses += [s for s in step.statuses if s.command == command.id]
        assert statuses[-1].state is CommandState.SUCCEEDED and statuses[-1].answer is expected[1], statuses
        asked, answered = events[-2:]
        assert (asked.kind, asked.actor, asked.target, asked.item) == (EventKind.ASK, "robot", "A1", question)
        got = (answered.kind, answered.actor, answered.target, answered.item, answered.answer)
        assert got == (EventKind.ANSWER, "A1", "robot", *expected), (
            f"expected the answer {expected}, got {got}"
        )
