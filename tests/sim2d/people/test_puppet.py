"""The puppet person (``toyroom play``'s participant) in the engine core: commands move it and
act, its scenario labels are completed in order so the scripted others go on, and the robot's
request, give or question waits for its answer (real pymunk world)."""

from __future__ import annotations

import itertools

import pytest

from protocol import (
    Ask,
    Cell,
    CommandState,
    CommandStatus,
    Direction,
    EventKind,
    Give,
    Navigate,
    PersonAction,
    PersonCommand,
    Request,
    RobotCommand,
)
from sim2d.engine import Engine
from sim2d.errors import Sim2dError
from sim2d.people.puppet import PuppetPerson, install_puppets

_ids = itertools.count()


def _engine() -> tuple[Engine, PuppetPerson]:
    engine = Engine("paper-robot")
    puppet = install_puppets(engine.people, engine.scenario, engine.world, ["A1"])["A1"]
    return engine, puppet


def _do(puppet: PuppetPerson, action: PersonAction, **fields: object) -> None:
    puppet.receive(PersonCommand(person="A1", action=action, seq=next(_ids), **fields))  # type: ignore[arg-type]


def _run(engine: Engine, ticks: int) -> list[tuple[str, str, str | None]]:
    """Step ``ticks`` ticks; the ``(actor, kind, label)`` of the people's events."""
    out = []
    for _ in range(ticks):
        for event in engine.step().events:
            out.append((event.actor, event.kind.value, event.label))
    return out


def test_commands_drive_the_person_and_its_labels_let_the_others_go_on() -> None:
    engine, puppet = _engine()
    _do(puppet, PersonAction.PLAY)
    events = _run(engine, 20)
    _do(puppet, PersonAction.GOTO, target="S1")
    _do(puppet, PersonAction.DROP)  # waits for the arrival
    _do(puppet, PersonAction.GOTO, target="E")
    _do(puppet, PersonAction.GOTO, target="O")
    events += _run(engine, 300)
    labels = [label for actor, kind, label in events if actor == "A1" and kind == "waypoint"]
    assert labels == ["0", "1", "2", "3", "4"], f"A1's labels completed: {labels}"
    assert ("A1", "drop", None) in events, "the drop never happened"
    assert ("A2", "waypoint", "swapped") in events, "A2 never swapped: it waits on A1's label 4"
    assert engine.world.items["skate"].holder == "A2"


def test_a_step_into_a_wall_does_nothing_and_a_held_key_does_not_run_on() -> None:
    engine, puppet = _engine()
    start = engine.world.agents["A1"].cell  # (1, 9): the west wall is at column -1
    _do(puppet, PersonAction.MOVE, direction=Direction.LEFT)
    _do(puppet, PersonAction.MOVE, direction=Direction.LEFT)
    _run(engine, 20)
    assert engine.world.agents["A1"].cell == (start[0] - 1, start[1]), "one step left, then the wall"
    for _ in range(6):
        _do(puppet, PersonAction.MOVE, direction=Direction.RIGHT)
    _run(engine, 40)
    assert engine.world.agents["A1"].cell == (start[0] + 1, start[1]), "more than two queued steps ran on"


def _command(engine: Engine, action: object) -> str:
    command = RobotCommand(id=f"c{next(_ids)}", robot="robot", action=action)  # type: ignore[arg-type]
    engine.command(command)
    return command.id


def _until_final(engine: Engine, command: str, ticks: int) -> CommandStatus | None:
    for _ in range(ticks):
        final = [s for s in engine.step().statuses if s.command == command and s.state.final]
        if final:
            return final[0]
    return None


def test_the_robot_waits_for_the_participants_answer() -> None:
    engine, puppet = _engine()
    _command(engine, Navigate(cell=Cell(2, 9)))  # beside A1, who holds the skate
    _run(engine, 60)
    asked = _command(engine, Request(person="A1", item="skate"))
    assert _until_final(engine, asked, 60) is None, "the request ended without the participant's answer"
    assert puppet.deciding, "the puppet has no open question"
    _do(puppet, PersonAction.DECLINE)
    status = _until_final(engine, asked, 5)
    assert status is not None and status.state is CommandState.SUCCEEDED and status.answer is False, status
    _do(puppet, PersonAction.ACCEPT)  # no question open: nothing happens
    asked = _command(engine, Request(person="A1", item="skate"))
    _run(engine, 3)
    _do(puppet, PersonAction.ACCEPT)
    status = _until_final(engine, asked, 20)
    assert status is not None and status.answer is True, status
    assert engine.world.agents["robot"].holding == "skate"
    given = _command(engine, Give(person="A1"))
    _do(puppet, PersonAction.DECLINE)  # before the give opens its question: ignored
    assert _until_final(engine, given, 40) is None, "the give ended without the participant's answer"
    _do(puppet, PersonAction.DECLINE)
    status = _until_final(engine, given, 5)
    assert status is not None and status.state is CommandState.FAILED, status
    assert "declined" in status.reason, status.reason
    kinds = [e.kind for e in engine.step().events]
    assert EventKind.GIVE not in kinds


def test_an_unknown_person_is_refused_by_name() -> None:
    engine = Engine("paper-robot")
    with pytest.raises(Sim2dError, match=r"--puppet A9: no such person .*people: A1, A2"):
        install_puppets(engine.people, engine.scenario, engine.world, ["A9"])


def _answers(engine: Engine, command: str, ticks: int) -> tuple[CommandStatus | None, list[tuple]]:
    """Step until ``command`` ends (at most ``ticks``): its final status, and the ``answer``
    events meanwhile as ``(actor, item, answer, target)``."""
    said = []
    for _ in range(ticks):
        out = engine.step()
        said += [(e.actor, e.item, e.answer, e.target) for e in out.events if e.kind is EventKind.ANSWER]
        final = [s for s in out.statuses if s.command == command and s.state.final]
        if final:
            return final[0], said
    return None, said


def test_the_participant_answers_the_robots_questions() -> None:
    engine, puppet = _engine()
    _command(engine, Navigate(cell=Cell(2, 9)))  # beside A1
    _run(engine, 60)
    what = _command(engine, Ask(person="A1"))
    status, said = _answers(engine, what, 60)
    assert status is None and puppet.question is not None and puppet.question.kind == "what", (
        f"expected the open question to wait for the participant, got {status} and {puppet.question}"
    )
    _do(puppet, PersonAction.ACCEPT, item="kite")  # no such item: no answer, the question stays
    _run(engine, 2)
    assert puppet.deciding, "an answer naming no item of the scene closed the question"
    _do(puppet, PersonAction.ACCEPT, item="ball")
    status, said = _answers(engine, what, 20)
    assert status is not None and status.state is CommandState.SUCCEEDED and status.answer is True, status
    assert said == [("A1", "ball", True, "robot")], f"expected A1 to name the ball, got {said}"
    yes_no = _command(engine, Ask(person="A1", item="skate"))
    _run(engine, 3)
    _do(puppet, PersonAction.DECLINE)
    status, said = _answers(engine, yes_no, 20)
    assert status is not None and status.answer is False, status
    assert said == [("A1", "skate", False, "robot")], f"expected a no about the skate, got {said}"
    nothing = _command(engine, Ask(person="A1"))
    _run(engine, 3)
    _do(puppet, PersonAction.DECLINE)
    status, said = _answers(engine, nothing, 20)
    assert said == [("A1", None, False, "robot")], f"expected 'nothing', got {said}"
    unanswered = _command(engine, Ask(person="A1"))
    status, said = _answers(engine, unanswered, 400)
    assert status is not None and status.state is CommandState.FAILED and "no answer" in status.reason, status
    assert said == [] and not puppet.deciding, f"no answer expected, got {said}"
