"""The robot's words as one person hears them (pure: no I/O).

The robot's ``say``, ``request``, ``give`` and ``ask`` commands are on the wire
(``robot/<id>/command``) and so is the moment each starts (its ``running`` status): that is
when the person hears it, if it is said to them or in a room they are in. A ``request``, a
``give`` or an ``ask`` to the person is an open question until the command ends (the engine
waits for the person's answer).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from protocol import (
    EARSHOT_CELLS,
    Ask,
    CommandState,
    CommandStatus,
    Give,
    Request,
    RobotCommand,
    Say,
    SayTopic,
    State,
)


def in_earshot(state: State, person: str, robot: str) -> bool:
    """Whether ``person`` hears ``robot`` in ``state``: the same region, or within
    :data:`protocol.EARSHOT_CELLS` cells (as sim2d)."""
    agents = {a.id: a for a in state.agents}
    me, it = agents.get(person), agents.get(robot)
    if me is None or it is None:
        return False
    near = abs(me.cell.col - it.cell.col) + abs(me.cell.row - it.cell.row) <= EARSHOT_CELLS
    return near or me.region == it.region


@dataclass
class Heard:
    """What the person has heard so far, and the question open to them."""

    lines: list[dict[str, Any]] = field(default_factory=list)
    """``{"tick", "text", "to_you"}``, oldest first."""
    question: dict[str, Any] | None = None
    """``{"command", "kind", "text"}`` while the robot waits for the person's answer; ``kind``
    ``request``, ``give``, ``ask`` (yes or no) or ``what`` (what are you looking for?: with
    ``"answers"``, ``[{"key", "item", "name"}]``, the keys that name each item)."""


class Speech:
    """Turns the robot's commands into sentences for ``person``.

    Args:
        person: the participant's person id.
        names: display names of agents and items, by id.
        region_name: display names of the location ids said (their region's name).
        answers: the digit key that names each item in answer to "what are you looking
            for?" (:func:`toyroom.play.keys.digit_keys`).
    """

    def __init__(
        self,
        person: str,
        names: dict[str, str],
        region_name: dict[str, str],
        answers: dict[str, str] | None = None,
    ) -> None:
        self.person = person
        self.names = names
        self.region_name = region_name
        self.answers = answers or {}
        self.commands: dict[str, RobotCommand] = {}
        self.heard = Heard()

    def on_command(self, command: RobotCommand) -> None:
        """The brain sent ``command`` (kept until it runs)."""
        self.commands[command.id] = command

    def _name(self, ident: str | None) -> str:
        return self.names.get(ident or "", ident or "something")

    def sentence(self, command: RobotCommand, robot_holds: str | None) -> str | None:
        """What the robot says doing ``command`` (``None``: it says nothing)."""
        action = command.action
        if isinstance(action, Say):
            to = self._name(action.person)
            if action.topic is SayTopic.LOCATION:
                place = self.region_name
                said = [
                    f"the {self._name(t.item)} is in {place.get(t.location, t.location)} ({t.location})"
                    for t in action.told
                ]
                return f"{to}, {'; '.join(said)}."
            return f"{to}, {self._name(action.holder)} has the {self._name(action.item)}."
        if isinstance(action, Request):
            offer = f" I will give you the {self._name(action.offer)}." if action.offer else ""
            return f"{self._name(action.person)}, may I have the {self._name(action.item)}?{offer}"
        if isinstance(action, Give):
            return f"{self._name(action.person)}, here is the {self._name(robot_holds)}."
        if isinstance(action, Ask):
            if action.item is None:
                return f"{self._name(action.person)}, what are you looking for?"
            return f"{self._name(action.person)}, do you want the {self._name(action.item)}?"
        return None

    def on_status(self, status: CommandStatus, tick: int, hears: bool, robot_holds: str | None) -> bool:
        """A status of a robot command; ``hears``: the person is in earshot of the robot.
        Whether what the person hears or is asked changed."""
        command = self.commands.get(status.command)
        if command is None:
            return False
        question = self.heard.question
        if status.state.final:
            self.commands.pop(status.command, None)
            if question is not None and question["command"] == status.command:
                self.heard.question = None
                withdrawn = self._withdrawn(command, status, robot_holds)
                if withdrawn is not None:  # the page says so, not just closes the question
                    self.heard.lines.append({"tick": tick, "text": withdrawn, "to_you": True})
                return True
            return False
        if status.state is not CommandState.RUNNING:
            return False
        text = self.sentence(command, robot_holds)
        to_you = getattr(command.action, "person", None) == self.person
        if text is None or not (to_you or hears):
            return False
        self.heard.lines.append({"tick": tick, "text": text, "to_you": to_you})
        if to_you and isinstance(command.action, (Request, Give, Ask)):
            self.heard.question = self._question(command, text)
        return True

    def _withdrawn(self, command: RobotCommand, status: CommandStatus, robot_holds: str | None) -> str | None:
        """What the robot says when it ends its question without the person's answer
        (cancelled, or failed for another reason than a no); ``None`` when they answered."""
        answered = status.answer is not None or "declined" in status.reason
        if status.state is CommandState.SUCCEEDED or answered:
            return None
        action = command.action
        item = self._name(robot_holds if isinstance(action, Give) else getattr(action, "item", None))
        if isinstance(action, Give):
            return f"I take back my offer of the {item} (no answer came)."
        if isinstance(action, Request):
            return f"Never mind the {item}: I stop asking (no answer came)."
        return "Never mind: I stop waiting for your answer."

    def _question(self, command: RobotCommand, text: str) -> dict[str, Any]:
        """The open question of ``command`` as the page shows it (:attr:`Heard.question`)."""
        action = command.action
        kind = {Request: "request", Give: "give"}.get(type(action), "ask")
        if isinstance(action, Ask) and action.item is None:
            answers = [{"key": k, "item": i, "name": self._name(i)} for k, i in self.answers.items()]
            return {"command": command.id, "kind": "what", "text": text, "answers": answers}
        return {"command": command.id, "kind": kind, "text": text}
