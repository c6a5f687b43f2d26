"""The robot body: executes commands from the wire, one at a time in arrival order, and
reports their statuses. It never decides anything itself.

Each command is checked on arrival (unknown ids, a wall as destination, a robot that only
observes: ``failed`` at once, else ``accepted``); when its turn comes it is ``running``,
its preconditions are checked again (``failed`` with the reason when they do not hold),
and it ends ``succeeded``, ``failed`` or ``cancelled``.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Mapping

from protocol import (
    COMMAND_KINDS,
    EARSHOT_CELLS,
    AgentKind,
    Ask,
    Cancel,
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
    UnknownAction,
)

from .people.person import Person
from .people.puppet import PuppetPerson
from .world.world import World

MANIPULATION_TICKS = 3
"""Ticks a pick, place or give takes."""
SPEECH_TICKS = 10
"""Ticks saying something or asking (and getting the answer) takes."""
ANSWER_TICKS = 300
"""Ticks a ``request``, ``give`` or ``ask`` to a puppet (a participant,
:mod:`sim2d.people.puppet`) waits for the participant's answer beyond its own duration; then a
request's or give's answer is no, and an ask has none."""


class RobotBody:
    """Executes one robot's commands in a :class:`~sim2d.world.world.World`."""

    def __init__(self, robot_id: str, acts: bool, scenario_name: str) -> None:
        self.id = robot_id
        self.acts = acts
        self.scenario_name = scenario_name
        self.queue: deque[RobotCommand] = deque()
        self.running: RobotCommand | None = None
        self.seen: set[str] = set()
        self.ticks_left = 0
        self.pending: list[CommandStatus] = []
        self.waited = 0
        """Ticks the running command has waited for a puppet's answer."""
        self.asking: PuppetPerson | None = None
        """The puppet the running command asks (a request or a give), if any."""

    @property
    def idle(self) -> bool:
        return self.running is None and not self.queue

    def _status(
        self,
        world: World,
        command: RobotCommand,
        state: CommandState,
        reason: str = "",
        answer: bool | None = None,
    ) -> None:
        self.pending.append(
            CommandStatus(
                command=command.id, robot=self.id, state=state, tick=world.tick, reason=reason, answer=answer
            )
        )

    def _check_ids(self, world: World, command: RobotCommand) -> str | None:
        action = command.action
        people = {a for a, agent in world.agents.items() if agent.kind is AgentKind.PERSON}

        def unknown(kind: str, value: str | None, known: Mapping[str, object] | set[str]) -> str | None:
            if value is not None and value not in known:
                return f"unknown id '{value}': no such {kind} (known: {', '.join(sorted(known))})"
            return None

        if isinstance(action, Navigate):
            cell = (action.cell.col, action.cell.row)
            if cell not in world.walkable:
                return f"not walkable: ({cell[0]},{cell[1]}) is a wall or outside the map"
            return None
        if isinstance(action, Pick):
            return unknown("item", action.item, world.items)
        if isinstance(action, Place):
            return unknown("location", action.location, world.locations)
        if isinstance(action, Give):
            return unknown("person", action.person, people)
        if isinstance(action, Say):
            named: list[tuple[str, str | None, Mapping[str, object] | set[str]]] = [
                ("person", action.person, people),
                ("item", action.item, world.items),
                ("location", action.location, world.locations),
                ("agent", action.holder, world.agents),
            ]
            for told in action.also:
                named += [("item", told.item, world.items), ("location", told.location, world.locations)]
            return next(
                (problem for kind, value, known in named if (problem := unknown(kind, value, known))), None
            )
        if isinstance(action, Request):
            return (
                unknown("person", action.person, people)
                or unknown("item", action.item, world.items)
                or unknown("item", action.offer, world.items)
            )
        if isinstance(action, Ask):
            return unknown("person", action.person, people) or unknown("item", action.item, world.items)
        return None

    def receive(self, world: World, command: RobotCommand) -> None:
        """A command arrived: accept it (queue it) or fail it at once."""
        if command.robot != self.id:  # answered on the key of the robot it names, as any status
            reason = f"unknown robot '{command.robot}'; this engine's robot is '{self.id}'"
            failed = CommandStatus(
                command=command.id,
                robot=command.robot,
                state=CommandState.FAILED,
                tick=world.tick,
                reason=reason,
            )
            self.pending.append(failed)
            return
        if not self.acts:
            self._status(
                world,
                command,
                CommandState.FAILED,
                f"robot '{self.id}' only observes in scenario '{self.scenario_name}' (robot = observe)",
            )
            return
        if command.id in self.seen:
            self._status(world, command, CommandState.FAILED, f"duplicate command id '{command.id}'")
            return
        if isinstance(command.action, UnknownAction):
            kind = command.action.kind
            known = ", ".join(COMMAND_KINDS)
            self._status(
                world,
                command,
                CommandState.FAILED,
                f"unknown command kind '{kind}' (this engine does {known})",
            )
            return
        self.seen.add(command.id)
        problem = self._check_ids(world, command)
        if problem is not None:
            self._status(world, command, CommandState.FAILED, problem)
            return
        if isinstance(command.action, Cancel):
            self._cancel(world, command, command.action.command)
            return
        self._status(world, command, CommandState.ACCEPTED)
        self.queue.append(command)

    def _cancel(self, world: World, command: RobotCommand, target: str) -> None:
        victim = self.running if self.running is not None and self.running.id == target else None
        if victim is None:
            victim = next((c for c in self.queue if c.id == target), None)
            if victim is not None:
                self.queue.remove(victim)
        else:
            self.running = None
            self._close_ask()
            world.stop(self.id)
        if victim is None:
            self._status(world, command, CommandState.FAILED, f"no queued or running command '{target}'")
            return
        self._status(world, command, CommandState.ACCEPTED)
        self._status(world, victim, CommandState.CANCELLED, f"cancelled by '{command.id}'")
        self._status(world, command, CommandState.SUCCEEDED)

    def stop_all(self, world: World, reason: str) -> None:
        """Fail every queued and running command with ``reason`` and stop the body."""
        for command in ([self.running] if self.running is not None else []) + list(self.queue):
            self._status(world, command, CommandState.FAILED, reason)
        self.running = None
        self._close_ask()
        self.queue.clear()
        world.stop(self.id)

    def update(self, world: World, people: Mapping[str, Person]) -> None:
        """Carry the running command forward by one tick (starting the next when idle)."""
        if self.running is None:
            if not self.queue:
                return
            self.running = self.queue.popleft()
            self._status(world, self.running, CommandState.RUNNING)
            problem = self._start(world, self.running, people)
            if problem is not None:
                self._finish(world, CommandState.FAILED, problem)
                return
            self._ask(world, self.running.action, people)
        command = self.running
        assert command is not None
        action = command.action
        if isinstance(action, Navigate):
            if world.arrived(self.id):
                self._finish(world, CommandState.SUCCEEDED)
            return
        if self.ticks_left <= 1 and self._deciding():
            return
        self.ticks_left -= 1
        if self.ticks_left > 0:
            return
        problem, answer = self._complete(world, action, people)
        if problem is not None:
            self._finish(world, CommandState.FAILED, problem)
        else:
            self._finish(world, CommandState.SUCCEEDED, answer=answer)

    def _ask(self, world: World, action: object, people: Mapping[str, Person]) -> None:
        """A request, a give or an ask to a puppet (a participant) opens its question at the
        start."""
        person = people.get(getattr(action, "person", ""))
        if isinstance(person, PuppetPerson) and isinstance(action, (Request, Give, Ask)):
            if isinstance(action, Request):
                person.ask("request", action.item, action.offer)
            elif isinstance(action, Ask):
                person.ask("ask" if action.item is not None else "what", action.item or "")
            else:
                person.ask("give", world.agents[self.id].holding or "")
            self.asking = person

    def _deciding(self) -> bool:
        """Whether the puppet asked is still deciding (the command then waits, up to
        :data:`ANSWER_TICKS`)."""
        if self.asking is None or not self.asking.deciding:
            return False
        self.waited += 1
        return self.waited <= ANSWER_TICKS

    def _finish(
        self, world: World, state: CommandState, reason: str = "", answer: bool | None = None
    ) -> None:
        assert self.running is not None
        self._status(world, self.running, state, reason, answer)
        self.running = None
        self._close_ask()

    def _close_ask(self) -> None:
        """The running command is over: the puppet it asked has no open question."""
        self.waited = 0
        if self.asking is not None:
            self.asking.question = self.asking.reply = None
            self.asking = None

    def _answered(self, world: World, action: Ask, person: Person | None) -> tuple[str | None, bool | None]:
        """The person's answer to an ``ask``: an ``answer`` event and the status' yes or no;
        ``no answer`` when they give none (busy, ``Autonomy.silent``)."""
        said = person.says_wanted(world, action.item) if person is not None else None
        if said is None:
            return f"no answer: {action.person} did not answer", None
        item, wants = said
        world.emit(EventKind.ANSWER, action.person, item=item, target=self.id, answer=wants)
        return None, wants

    def _reach(self, world: World, person: str) -> str | None:
        me, them = world.agents[self.id].cell, world.agents[person].cell
        if not world.within_reach(me, them):
            return f"out of reach: {person} is at ({them[0]},{them[1]}), the robot at ({me[0]},{me[1]})"
        return None

    def _start(self, world: World, command: RobotCommand, people: Mapping[str, Person]) -> str | None:
        """Check preconditions and set the command going; the reason when it cannot start."""
        action = command.action
        me = world.agents[self.id]
        if isinstance(action, Navigate):
            if not world.plan_to(self.id, (action.cell.col, action.cell.row)):
                return f"unreachable: no path to ({action.cell.col},{action.cell.row})"
            return None
        if isinstance(action, (Say, Request, Ask)):
            self.ticks_left = SPEECH_TICKS
            person = world.agents[action.person]
            near = abs(person.cell[0] - me.cell[0]) + abs(person.cell[1] - me.cell[1]) <= EARSHOT_CELLS
            if isinstance(action, (Say, Ask)):
                if not near and person.region != me.region:
                    return (
                        f"out of earshot: {action.person} is in {person.region} "
                        f"({person.cell[0]},{person.cell[1]}), "
                        f"the robot in {me.region} ({me.cell[0]},{me.cell[1]})"
                    )
                if isinstance(action, Ask):
                    world.emit(EventKind.ASK, self.id, item=action.item, target=action.person)
                return None
            if person.holding != action.item:
                return f"{action.person} does not hold '{action.item}'"
            if me.holding is not None and me.holding != action.offer:
                return f"hands full: the robot holds '{me.holding}'"
            problem = self._reach(world, action.person)
            if problem is None:
                world.emit(
                    EventKind.REQUEST, self.id, item=action.item, target=action.person, offer=action.offer
                )
            return problem
        self.ticks_left = MANIPULATION_TICKS
        return self._check(world, action)

    def _check(self, world: World, action: object) -> str | None:
        me = world.agents[self.id]
        if isinstance(action, Pick):
            item = world.items[action.item]
            if me.holding is not None:
                return f"hands full: the robot holds '{me.holding}'"
            if item.holder is not None:
                return f"item held by {item.holder}"
            if not world.within_reach(me.cell, world.item_cell(action.item)):
                c = world.item_cell(action.item)
                return (
                    f"item not there: '{action.item}' is at {item.location} ({c[0]},{c[1]}), "
                    "out of the robot's reach"
                )
            return None
        if isinstance(action, Place):
            loc = world.locations[action.location]
            if me.holding is None:
                return "hands empty: the robot holds nothing"
            if not world.within_reach(me.cell, (loc.cell.col, loc.cell.row)):
                return f"out of reach: location {loc.id} is at ({loc.cell.col},{loc.cell.row})"
            return None
        if isinstance(action, Give):
            person = world.agents[action.person]
            if me.holding is None:
                return "hands empty: the robot holds nothing"
            if person.holding is not None:
                return f"{action.person}'s hands are full: holds '{person.holding}'"
            return self._reach(world, action.person)
        return None

    def _complete(
        self, world: World, action: object, people: Mapping[str, Person]
    ) -> tuple[str | None, bool | None]:
        """Finish a timed command; ``(reason it failed, answer)``."""
        problem = self._check(world, action)
        if problem is not None:
            return problem, None
        if isinstance(action, Pick):
            return world.take(self.id, action.item), None
        if isinstance(action, Place):
            return world.drop(self.id, action.location), None
        if isinstance(action, Give):
            puppet = people.get(action.person)
            if isinstance(puppet, PuppetPerson) and not puppet.close_question():
                return f"{action.person} declined '{world.agents[self.id].holding}'", None
            world.hand_over(self.id, action.person)
            if action.person in people:
                people[action.person].on_given(world)
            return None, None
        if isinstance(action, Say):
            if action.topic is SayTopic.LOCATION:
                for told in action.told:  # one event per item told (``also``, from 1.6), this tick
                    world.emit(
                        EventKind.SAY, self.id, item=told.item, location=told.location, target=action.person
                    )
                    if action.person in people:
                        people[action.person].on_informed(world, told.item, told.location)
            else:
                world.emit(
                    EventKind.SAY,
                    self.id,
                    item=action.item,
                    target=action.person,
                    detail=f"occupied by {action.holder}",
                )
            return None, None
        if isinstance(action, Ask):
            return self._answered(world, action, people.get(action.person))
        assert isinstance(action, Request)
        person = people.get(action.person)
        still = world.agents[action.person].holding == action.item
        answer = bool(person is not None and still and person.answer(world, action.item, action.offer))
        world.emit(EventKind.REPLY, action.person, item=action.item, target=self.id, answer=answer)
        if answer:
            me = world.agents[self.id]
            if me.holding is not None:  # the robot carries the offer: swap at once
                world.swap(action.person, self.id)
                assert person is not None
                person.on_given(world)
            else:
                world.hand_over(action.person, self.id)
                assert person is not None
                person.on_handed_over(world)
        return None, answer
