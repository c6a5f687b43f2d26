"""A puppet person: a human drives it from the wire (``person/<id>/command``, protocol
:class:`~protocol.person.PersonCommand`) instead of its script (``toyroom play``).

Moves (``move``, ``goto``, ``stop``) take effect on the next tick; the discrete actions
(``take``, ``drop``, ``play``) wait, as a scripted person's do, until the person stands on a
cell centre, one per tick. The robot's questions (a ``request`` to hand over or swap, a
``give``, an ``ask``) stay open until the participant answers (``accept``, ``decline``; to
"what are you looking for?", ``accept`` names the item; the robot body waits,
:mod:`sim2d.robot`). The person's scenario labels are completed as the person reaches
them (entering the region, dropping, playing...), in order (a missed action is skipped when
the next is reached), so that the other people's ``until`` steps fire as they would with the script.
"""

from __future__ import annotations

import logging
from collections import deque
from collections.abc import Iterable, MutableMapping
from dataclasses import dataclass

from protocol import STEP_OF, EventKind, PersonAction, PersonCommand

from ..errors import Sim2dError
from ..scenario.scenario import AgentSetup, Scenario
from ..scenario.script import Drop, Enter, Goto, Play, Step, Take
from ..world.world import World
from .person import Person

log = logging.getLogger("toyroom.sim2d")

MOVES = (PersonAction.MOVE, PersonAction.GOTO, PersonAction.STOP)
ANSWERS = (PersonAction.ACCEPT, PersonAction.DECLINE)
QUEUED_CELLS = 2
"""At most this many cells of ``move`` steps ahead (a held arrow key does not run on)."""


@dataclass(frozen=True)
class OpenQuestion:
    """The robot's open question to the puppet: ``request`` (hand over ``item``, for
    ``offer``), ``give`` (take ``item`` from the robot), ``ask`` (do you want ``item``?) or
    ``what`` (what are you looking for?: answered by accepting with an item, or declining for
    nothing)."""

    kind: str
    item: str
    offer: str | None = None


class PuppetPerson:
    """One person driven by a participant's commands (a :class:`~.person.Person`)."""

    def __init__(self, setup: AgentSetup, world: World) -> None:
        self.setup = setup
        self.id = setup.id
        self.world = world
        self.inbox: deque[PersonCommand] = deque()
        """Commands as they arrive (appended from the network's thread, taken in :meth:`update`)."""
        self.waiting: deque[PersonCommand] = deque()
        """Commands not yet carried out, in order (a discrete action holds up those after it)."""
        self.labels: list[tuple[Step, str]] = [(s, s.label) for s in setup.script if s.label is not None]
        self.question: OpenQuestion | None = None
        self.reply: bool | None = None
        self.named: str | None = None
        """The item the participant named in answer to a ``what`` question."""
        self._done_now: set[tuple[str, str | None]] = set()
        """This tick's actions, as ``(kind, item)``, for the labels."""

    @property
    def finished(self) -> bool:
        """Settled: playing (the episode may end once the robot idles too)."""
        return self.world.agents[self.id].playing

    def receive(self, command: PersonCommand) -> None:
        """A command from the wire (any thread)."""
        self.inbox.append(command)

    def update(self, world: World) -> None:
        """Carry out this tick's commands in order (a discrete action waits, and the commands
        after it, until the person stands on a cell centre; one per tick); complete the labels
        reached."""
        self._done_now = set()
        while self.inbox:
            self.waiting.append(self.inbox.popleft())
        acted = False
        while self.waiting:
            command = self.waiting[0]
            if command.action in MOVES:
                self._move(world, command)
            elif command.action in ANSWERS:
                self._reply(world, command)
            elif acted or not world.arrived(self.id):
                break
            else:
                self._act(world, command)
                acted = True
            self.waiting.popleft()
        self._complete_labels(world)

    # ----- commands -------------------------------------------------------------------

    def _reply(self, world: World, command: PersonCommand) -> None:
        """A yes or a no to the open question; to a ``what`` question, a yes names the item
        wanted (an unknown or missing item is no answer: the question stays open)."""
        if self.question is None:
            return
        yes = command.action is PersonAction.ACCEPT
        if self.question.kind == "what" and yes:
            if command.item not in world.items:
                log.info("%s: answer names '%s', which is not an item", self.id, command.item)
                return
            self.named = command.item
        self.reply = yes

    def _stop_playing(self, world: World) -> None:
        agent = world.agents[self.id]
        if agent.playing:
            agent.playing = False
            world.emit(EventKind.STOP, self.id, item=agent.holding)

    def _move(self, world: World, command: PersonCommand) -> None:
        agent = world.agents[self.id]
        if command.action is PersonAction.STOP:
            world.stop(self.id)
            return
        self._stop_playing(world)
        if command.action is PersonAction.GOTO:
            target = command.target or ""
            if target in world.locations:
                cell = world.locations[target].cell
                ok = world.plan_to(self.id, (cell.col, cell.row))
            elif target in world.region_cells:
                ok = world.plan_to_region(self.id, target)
            else:
                log.info("%s: goto '%s': no such location or region", self.id, target)
                return
            if not ok:
                log.info("%s: goto '%s': unreachable", self.id, target)
            return
        assert command.direction is not None
        dcol, drow = STEP_OF[command.direction]
        base = agent.path[-1] if agent.path else agent.cell
        nxt = (base[0] + dcol, base[1] + drow)
        if nxt in world.walkable and len(agent.path) < QUEUED_CELLS:
            agent.path.append(nxt)

    def _act(self, world: World, command: PersonCommand) -> None:
        agent = world.agents[self.id]
        reason: str | None = None
        if command.action is PersonAction.TAKE:
            item = command.item or self._item_within_reach(world)
            reason = "nothing within reach" if item is None else world.take(self.id, item)
            if reason is None:
                self._done_now.add(("take", item))
        elif command.action is PersonAction.DROP:
            location = self._location_within_reach(world)
            reason = "no item spot within reach" if location is None else world.drop(self.id, location)
            if reason is None:
                self._done_now.add(("drop", None))
        elif agent.playing:
            self._stop_playing(world)
        elif agent.holding is None:
            reason = "nothing to play with"
        else:
            agent.playing = True
            spot = world.location_at.get(agent.cell)
            world.emit(EventKind.PLAY, self.id, item=agent.holding, location=spot.id if spot else None)
            self._done_now.add(("play", None))
        if reason is not None:
            log.info("%s: %s failed: %s", self.id, command.action.value, reason)

    def _item_within_reach(self, world: World) -> str | None:
        cell = world.agents[self.id].cell
        resting = [i for i in world.items.values() if i.location is not None]
        near = [i.id for i in resting if world.within_reach(cell, world.item_cell(i.id))]
        return near[0] if near else None

    def _location_within_reach(self, world: World) -> str | None:
        cell = world.agents[self.id].cell
        here = world.location_at.get(cell)
        if here is not None:
            return here.id
        near = [
            loc.id
            for loc in world.locations.values()
            if world.within_reach(cell, (loc.cell.col, loc.cell.row))
        ]
        return near[0] if near else None

    # ----- labels ---------------------------------------------------------------------

    def _reached(self, world: World, step: Step) -> bool:
        agent = world.agents[self.id]
        if isinstance(step, Enter):
            return world.region_of.get(agent.cell) == step.region
        if isinstance(step, Goto):
            return agent.cell == step.cell and world.arrived(self.id)
        if isinstance(step, Take):
            return ("take", step.item) in self._done_now
        if isinstance(step, Drop):
            return ("drop", None) in self._done_now
        if isinstance(step, Play):
            return ("play", None) in self._done_now
        return False

    def _complete_labels(self, world: World) -> None:
        """Complete the labels in order as the person reaches them; a missed action (take,
        drop, play) is skipped when the person reaches the next (playing first, say, is not
        required), a place never (the same room may come again later in the route)."""
        while self.labels:
            first = self.labels[0][0]
            skippable = isinstance(first, (Take, Drop, Play)) and len(self.labels) > 1
            if self._reached(world, first):
                reached = 0
            elif skippable and self._reached(world, self.labels[1][0]):
                reached = 1
            else:
                return
            world.complete(self.id, self.labels[reached][1])
            del self.labels[: reached + 1]

    # ----- the robot's questions ------------------------------------------------------

    def ask(self, kind: str, item: str, offer: str | None = None) -> None:
        """The robot opens a question (its body waits for :attr:`reply`)."""
        self.question = OpenQuestion(kind, item, offer)
        self.reply = None

    @property
    def deciding(self) -> bool:
        """Whether a question is open and not yet answered."""
        return self.question is not None and self.reply is None

    def close_question(self) -> bool:
        """The answer to the open question (no answer: no), the question closed."""
        answer = bool(self.reply)
        self.question, self.reply, self.named = None, None, None
        return answer

    def answer(self, world: World, item: str, offer: str | None = None) -> bool:
        """Hand over ``item``? The participant's answer (as the person still holds it)."""
        return self.close_question() and world.agents[self.id].holding == item

    def says_wanted(self, world: World, item: str | None) -> tuple[str | None, bool] | None:
        """The participant's answer to the robot's ``ask`` (``None``: they gave none in time):
        about ``item``, yes or no; to an open question, the item they named (and yes), or
        nothing (``None`` and no)."""
        if self.question is None or self.reply is None:
            self.close_question()
            return None
        named, yes = self.named, self.close_question()
        if item is not None:
            return item, yes
        return (named, True) if yes else (None, False)

    def on_given(self, world: World) -> None:
        """Handed an item: the participant decides what to do with it."""

    def on_informed(self, world: World, item: str, location: str) -> None:
        """Told where ``item`` is: the participant heard it on their page."""

    def on_handed_over(self, world: World) -> None:
        """Gave away what they held: nothing more to do."""


def install_puppets(
    people: MutableMapping[str, Person], scenario: Scenario, world: World, ids: Iterable[str]
) -> dict[str, PuppetPerson]:
    """Put a puppet in place of each person of ``ids`` (in ``people``, the engine's); the puppets.

    Raises:
        Sim2dError: an id that is not a person of the scenario, naming those that are.
    """
    setups = {s.id: s for s in scenario.people}
    puppets: dict[str, PuppetPerson] = {}
    for person_id in ids:
        if person_id not in setups:
            known = ", ".join(sorted(setups))
            raise Sim2dError(
                f"--puppet {person_id}: no such person in scenario '{scenario.name}' (people: {known})"
            )
        puppets[person_id] = people[person_id] = PuppetPerson(setups[person_id], world)
    return puppets
