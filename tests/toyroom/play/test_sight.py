"""What the participant's page is sent (pure parts): what the person sees by the scene's
visibility, what they remember, what they hear the robot say, and the keyboard."""

from __future__ import annotations

import pytest

from protocol import (
    Ask,
    CommandState,
    CommandStatus,
    Direction,
    Give,
    PersonAction,
    RobotCommand,
    Say,
    SayTopic,
)
from sim2d.engine import Engine
from toyroom.play import Memory, Sight, Speech, command_for, digit_keys, goto_keys


@pytest.fixture
def engine() -> Engine:
    return Engine("paper-robot")


def test_the_person_sees_their_rooms_only_and_remembers_the_rest(engine: Engine) -> None:
    sight = Sight(engine.scene(), "A1")
    memory = Memory()
    view = sight.look(engine.state(), memory)
    assert view["regions"] == ["P1", "S1"] and view["locations"] == ["P1", "S1"], view
    assert [a["id"] for a in view["agents"]] == ["A1"], f"A1 sees {view['agents']} from P1 (A2 is in P2)"
    assert [i["id"] for i in view["items"]] == ["skate"], "A1 sees the ball A2 holds in P2"
    memory.note("ball", "S2", 0)
    faded = [i for i in sight.look(engine.state(), memory)["items"] if i["faded"]]
    assert [(i["id"], i["x"], i["y"]) for i in faded] == [("ball", 9.5, 10.5)], faded
    assert memory.places == {"skate": "P1", "ball": "S2"}, "the skate, seen in A1's hands, is at P1"


def test_the_layout_numbers_the_places(engine: Engine) -> None:
    keys = goto_keys(engine.scene())
    assert keys == {"1": "P1", "2": "S1", "3": "S2", "4": "P2", "5": "E", "6": "O"}, keys


def test_the_robot_is_heard_and_its_give_is_a_question() -> None:
    speech = Speech("A1", {"A1": "Agent 1", "A2": "Agent 2", "skate": "skate"}, {"S1": "Storage 1"})
    told = RobotCommand(
        id="c1", robot="robot", action=Say(person="A1", item="skate", topic=SayTopic.OCCUPIED, holder="A2")
    )
    given = RobotCommand(id="c2", robot="robot", action=Give(person="A1"))
    other = RobotCommand(
        id="c3", robot="robot", action=Say(person="A2", item="skate", topic=SayTopic.LOCATION, location="S1")
    )
    for command in (told, given, other):
        speech.on_command(command)

    def status(command: str, state: CommandState) -> CommandStatus:
        return CommandStatus(command=command, robot="robot", state=state, tick=5)

    assert speech.on_status(status("c1", CommandState.RUNNING), 5, hears=False, robot_holds=None)
    assert not speech.on_status(status("c3", CommandState.RUNNING), 6, hears=False, robot_holds=None), (
        "A1 heard what the robot said to A2 out of earshot"
    )
    assert speech.on_status(status("c2", CommandState.RUNNING), 7, hears=True, robot_holds="skate")
    texts = [line["text"] for line in speech.heard.lines]
    assert texts == ["Agent 1, Agent 2 has the skate.", "Agent 1, here is the skate."], texts
    assert speech.heard.question is not None and speech.heard.question["kind"] == "give"
    assert speech.on_status(status("c2", CommandState.SUCCEEDED), 9, hears=True, robot_holds=None)
    assert speech.heard.question is None, "the question stayed open after the give ended"


def test_the_robot_says_when_it_withdraws_its_offer() -> None:
    """Issue 55: a give the brain cancelled closed the question without a word."""
    speech = Speech("A1", {"A1": "Agent 1", "skate": "skate"}, {})
    for n, (end, reason) in enumerate(
        [(CommandState.CANCELLED, "cancelled by 'c6'"), (CommandState.FAILED, "A1 declined 'skate'")]
    ):
        speech.on_command(RobotCommand(id=f"g{n}", robot="robot", action=Give(person="A1")))
        speech.on_status(
            CommandStatus(command=f"g{n}", robot="robot", state=CommandState.RUNNING, tick=1),
            1,
            True,
            "skate",
        )
        assert speech.heard.question is not None
        ended = CommandStatus(command=f"g{n}", robot="robot", state=end, tick=2, reason=reason)
        assert speech.on_status(ended, 2, hears=True, robot_holds="skate")
        assert speech.heard.question is None
    texts = [line["text"] for line in speech.heard.lines]
    assert texts.count("I take back my offer of the skate (no answer came).") == 1, (
        f"one withdrawal said, for the cancelled give, none for the declined one: {texts}"
    )


def test_keys_become_commands_with_their_time() -> None:
    goto = {"2": "S1"}
    up = command_for("ArrowUp", "A1", 3, goto, pressed=1.25, participant="p1")
    assert up is not None and up.action is PersonAction.MOVE and up.direction is Direction.UP
    assert (up.key, up.pressed, up.seq, up.participant) == ("ArrowUp", 1.25, 3, "p1")
    walk = command_for("2", "A1", 4, goto)
    assert walk is not None and walk.action is PersonAction.GOTO and walk.target == "S1"
    assert [command_for(k, "A1", 0, goto).action for k in "tdpyn"] == [  # type: ignore[union-attr]
        PersonAction.TAKE, PersonAction.DROP, PersonAction.PLAY, PersonAction.ACCEPT, PersonAction.DECLINE,
    ]  # fmt: skip
    assert command_for("q", "A1", 0, goto) is None and command_for("9", "A1", 0, goto) is None


def test_the_robots_question_names_the_items_and_digits_answer_it() -> None:
    answers = digit_keys(["skate", "ball"])
    assert answers == {"1": "skate", "2": "ball"}, answers
    speech = Speech("A1", {"A1": "Agent 1", "ball": "ball", "skate": "skate"}, {}, answers)
    what = RobotCommand(id="c1", robot="robot", action=Ask(person="A1"))
    yes_no = RobotCommand(id="c2", robot="robot", action=Ask(person="A1", item="ball"))
    for command in (what, yes_no):
        speech.on_command(command)
    running = CommandStatus(command="c1", robot="robot", state=CommandState.RUNNING, tick=5)
    assert speech.on_status(running, 5, hears=True, robot_holds=None)
    question = speech.heard.question
    assert question is not None and question["kind"] == "what", question
    assert question["text"] == "Agent 1, what are you looking for?", question
    assert [(a["key"], a["item"]) for a in question["answers"]] == [("1", "skate"), ("2", "ball")], question
    named = command_for("2", "A1", 0, {"2": "S1"}, answers=answers)
    assert named is not None and (named.action, named.item) == (PersonAction.ACCEPT, "ball"), (
        f"while asked what A1 looks for, 2 names the ball (not a walk to S1): got {named}"
    )
    nothing = command_for("n", "A1", 0, {"2": "S1"}, answers=answers)
    assert nothing is not None and nothing.action is PersonAction.DECLINE
    done = CommandStatus(command="c1", robot="robot", state=CommandState.SUCCEEDED, tick=8)
    speech.on_status(done, 8, hears=True, robot_holds=None)
    running = CommandStatus(command="c2", robot="robot", state=CommandState.RUNNING, tick=9)
    speech.on_status(running, 9, hears=True, robot_holds=None)
    assert speech.heard.question is not None and speech.heard.question["kind"] == "ask"
    assert speech.heard.question["text"] == "Agent 1, do you want the ball?", speech.heard.question
