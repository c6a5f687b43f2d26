"""Scripted people: they follow their scenario route step by step and react to the robot.

Reactions (they replace what is left of the route):
- handed an item: walk to the nearest play spot and play with it;
- told where the item they want is: go there, take it, play with it at the nearest play spot;
- asked to hand over what they hold: answer as the scenario says; on yes, hand it over and wait.
A person performs at most one discrete action (take, drop, start playing) per tick, and
never in the tick it arrives somewhere, so each is a separate decision an observer can see.
"""

from __future__ import annotations

import enum
import logging
from dataclasses import dataclass

from protocol import EventKind

from ..scenario.scenario import AgentSetup
from ..scenario.script import Drop, Enter, Goto, Play, Step, Take, Use, Wait
from ..world.world import Agent, World

log = logging.getLogger("toyroom.sim2d")


@dataclass(frozen=True)
class GotoPlaySpot:
    """Walk to the nearest play spot (resolved when the step starts)."""

    label: str | None = None


PlanStep = Step | GotoPlaySpot


class After(enum.Enum):
    """What a step's handler says: go on to the next step this tick, or wait for the next tick."""

    STEP = "step"
    TICK = "tick"


class ScriptedPerson:
    """Drives one person of a scenario."""

    def __init__(self, setup: AgentSetup) -> None:
        self.setup = setup
        self.id = setup.id
        self.plan: list[PlanStep] = list(setup.script)
        self.index = 0
        self.started = False
        self.ticks_left = 0
        self.goal: object = None
        self.acted = False
        """Whether the person already took a discrete action (take, drop, play) this tick."""

    @property
    def finished(self) -> bool:
        """Whether the route is done (or the person has settled into playing or waiting for good)."""
        if self.index >= len(self.plan):
            return True
        step = self.plan[self.index]
        return self.started and isinstance(step, (Play, Wait)) and step.ticks is None and step.until is None

    def _advance(self, world: World, label: str | None) -> None:
        world.complete(self.id, label)
        self.index += 1
        self.started = False

    def _replace(self, plan: list[PlanStep]) -> None:
        self.plan = plan
        self.index = 0
        self.started = False

    def update(self, world: World) -> None:
        """Carry the route forward by one tick: finish steps until one has to wait."""
        agent = world.agents[self.id]
        self.acted = False
        while self.index < len(self.plan):
            step = self.plan[self.index]
            if isinstance(step, (Enter, Goto, GotoPlaySpot)):
                after = self._move(world, agent, step)
            elif isinstance(step, (Take, Drop)):
                after = self._hand(world, agent, step)
            elif isinstance(step, Play):
                after = self._play(world, agent, step)
            elif isinstance(step, Use):
                after = self._use(world, agent, step)
            else:
                after = self._wait(world, step)
            if after is After.TICK:
                return

    def _move(self, world: World, agent: Agent, step: Enter | Goto | GotoPlaySpot) -> After:
        if not self.started:
            self.started = True
            if isinstance(step, Enter):
                ok = (
                    agent.region == step.region
                    and agent.cell in world.region_of
                    or (world.plan_to_region(self.id, step.region))
                )
            elif isinstance(step, Goto):
                ok = world.plan_to(self.id, step.cell)
            else:
                ok = world.plan_to_region_cells(self.id, world.play_spots())
            if not ok:
                log.warning("%s cannot reach the target of %s; skipping it", self.id, step)
                self._advance(world, None)
                return After.STEP
        if not world.arrived(self.id):
            return After.TICK
        if isinstance(step, Enter) and world.region_of.get(agent.cell) != step.region:
            return After.TICK
        self._advance(world, step.label)
        return After.STEP

    def _hand(self, world: World, agent: Agent, step: Take | Drop) -> After:
        if self.acted or not world.arrived(self.id):
            return After.TICK
        self.acted = True
        location = world.location_at.get(agent.cell)
        if isinstance(step, Take):
            reason = world.take(self.id, step.item)
        elif location is None:
            reason = f"no item spot at {agent.cell}"
        else:
            reason = world.drop(self.id, location.id)
        if reason is not None:
            log.info("%s: %s failed: %s", self.id, type(step).__name__.lower(), reason)
        self._advance(world, step.label if reason is None else None)
        return After.STEP

    def _play(self, world: World, agent: Agent, step: Play) -> After:
        if not self.started:
            if self.acted:
                return After.TICK
            self.started = True
            self.ticks_left = step.ticks or 0
            if agent.holding is None:
                log.info("%s has nothing to play with; skipping the play step", self.id)
                self._advance(world, None)
                return After.STEP
            self.acted = True
            agent.playing = True
            spot = world.location_at.get(agent.cell)
            world.emit(EventKind.PLAY, self.id, item=agent.holding, location=spot.id if spot else None)
            if step.label is not None:
                world.complete(self.id, step.label)
            return After.TICK
        if not agent.playing:  # the item was handed over meanwhile
            self._advance(world, None)
            return After.STEP
        if self._still_going(step, world):
            return After.TICK
        agent.playing = False
        world.emit(EventKind.STOP, self.id, item=agent.holding)
        self._advance(world, None)
        return After.STEP

    def _use(self, world: World, agent: Agent, step: Use) -> After:
        if not self.started:
            if self.acted or not world.arrived(self.id):
                return After.TICK
            self.started = True
            self.ticks_left = step.ticks or 0
            reason = world.use(self.id, step.item)
            if reason is not None:
                log.info("%s: use failed: %s", self.id, reason)
                self._advance(world, None)
                return After.STEP
            self.acted = True
            if step.label is not None:
                world.complete(self.id, step.label)
            return After.TICK
        if self._still_going(step, world):
            return After.TICK
        agent.playing = False
        world.emit(EventKind.STOP, self.id, item=step.item)
        self._advance(world, None)
        return After.STEP

    def _wait(self, world: World, step: Wait) -> After:
        if not self.started:
            self.started = True
            self.ticks_left = step.ticks or 0
            if step.label is not None:
                world.complete(self.id, step.label)
        if self._still_going(step, world):
            return After.TICK
        self._advance(world, None)
        return After.STEP

    def _still_going(self, step: Play | Use | Wait, world: World) -> bool:
        if step.ticks is not None:
            self.ticks_left -= 1
            return self.ticks_left > 0
        if step.until is not None:
            return (step.until.agent, step.until.label) not in world.labels
        return True

    # ----- reactions to the robot ----------------------------------------------------

    def on_given(self, world: World) -> None:
        """Handed an item: go and play with it."""
        world.stop(self.id)
        self._replace([GotoPlaySpot(), Play()])

    def on_informed(self, world: World, item: str, location: str) -> None:
        """Told where ``item`` is: fetch it when it is the item this person wants."""
        agent = world.agents[self.id]
        if item != self.setup.wants or agent.holding == item or agent.holding is not None:
            return
        loc = world.locations[location]
        world.stop(self.id)
        self._replace([Goto((loc.cell.col, loc.cell.row), loc.id), Take(item), GotoPlaySpot(), Play()])

    def answer(self, world: World, item: str, offer: str | None = None) -> bool:
        """Answer a request to hand over ``item`` (as the scenario says, whatever the offer)."""
        return self.setup.answers and world.agents[self.id].holding == item

    def says_wanted(self, world: World, item: str | None) -> tuple[str | None, bool] | None:
        """The scenario's ``wants``, truthfully (an open question: ``(wants, True)``)."""
        wanted = self.setup.wants
        if item is not None:
            return item, item == wanted
        return (wanted, True) if wanted is not None else (None, False)

    def on_handed_over(self, world: World) -> None:
        """Gave away what they held: stop and wait."""
        world.stop(self.id)
        self._replace([Wait()])
