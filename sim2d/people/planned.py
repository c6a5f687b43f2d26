"""Simulated people who act by the brain's own planner (``Autonomy.planner = "model"``), so
episodes with known parameters exist: the data a fit must recover them from.

A planned person perceives like every autonomous person (:class:`~sim2d.people.belief.PersonBelief`,
with whatever rich-minds knobs the scenario sets), remembers which items they last saw in
someone else's hands, and at each decision:

1. redraws their preference uniformly from their goals (which may keep it) with the
   table's hazard compounded over the decision times since their last decision
   (``1 - (1 - hazard) ** max(1, elapsed)``): the brain's preference-change model;
2. draws one planner action from :meth:`~sim2d.people.policytable.PolicyTable.choice` for their
   cell, held item and belief;
3. carries it out so the brain's tracker reads that action: a move walks to the neighbouring
   cell (the next decision comes the tick after arriving); Take, Drop and Use happen at once
   (the next decision the tick after); Play plays for ``Autonomy.play_ticks``. The ``k``-th
   Stay in a row stands still until ``wait_decisions - 1 + k`` decision times after the
   person's last decision the tracker sees (their last change of cell, take, drop, use or
   play): exactly when the tracker reads its ``k``-th Stay (``brain/tracking/waits.py``), so
   whatever comes next shows before it could read another (before the first such decision,
   which the tracker reads no wait before, one decision time). An action the world does not
   allow (a wall, an item that is not there: only the ``epsilon`` floor picks these) is
   carried out as a Stay.

Reaching the outside or playing ends the planner's episode: the person then waits
``Autonomy.wait_ticks`` (outside) or plays on, and decides again. ``Autonomy.switch``,
``mischief``, ``put_away``, ``search``, ``wander`` and ``replan`` do not apply: the planner
decides everything.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from protocol import EventKind
from protocol.itemvalue import HELD, RESTING, value_count, value_of

from ..scenario.autonomy import Autonomy
from ..scenario.scenario import AgentSetup
from ..world.world import World
from .autonomous import AutonomousPerson
from .policytable import PolicyTable


@dataclass
class Doing:
    """The action under way: ``move`` until arrived, else ``stand`` or ``play`` for ``ticks``."""

    kind: str
    ticks: int = 0


class PlannedPerson(AutonomousPerson):
    """A simulated person whose decisions are the brain's planner's (see the module docstring)."""

    def __init__(
        self,
        setup: AgentSetup,
        world: World,
        rng: np.random.Generator,
        autonomy: Autonomy,
        table: PolicyTable,
    ) -> None:
        super().__init__(setup, world, rng, autonomy)
        self.table = table
        self.doing: Doing | None = None
        self.ready_at = 0
        """The first tick of the next decision."""
        self.last_decision: float | None = None
        self.seen_decision: float | None = None
        """The engine time of the last decision the brain's tracker sees: a change of cell, or
        a take, drop, use or play (the tracker counts Stays from it; none before the first)."""
        self.stays = 0
        """Stays since then."""
        self.cell: tuple[int, int] | None = None
        self.held_by_others: set[str] = set()
        """Items last seen in someone else's hands (value ``2 l + 1`` in the planner's worlds)."""
        self.decisions: list[tuple[int, str, float]] = []
        """Every decision: (tick, action name, the probability it was drawn with)."""

    def _saw(self, world: World, seen: dict[str, str]) -> None:
        for item in seen:
            holder = world.items[item].holder
            if holder is not None and holder != self.id:
                self.held_by_others.add(item)
            else:
                self.held_by_others.discard(item)

    def update(self, world: World) -> None:
        cell = world.agents[self.id].cell
        if cell != self.cell:  # it changed in the last tick's physics: that tick's state shows it
            if self.cell is not None:
                self._seen(world, world.tick - 1)
            self.cell = cell
        self.belief.forget(self.autonomy.forget_per_tick)
        self.perceive(world)
        if self.doing is not None and not self._continue(world):
            return
        if world.tick >= self.ready_at:
            self._decide(world)

    def _continue(self, world: World) -> bool:
        """Go on with the action under way; ``True`` once it is over (a decision may follow)."""
        assert self.doing is not None
        if self.doing.kind == "move":
            if not world.arrived(self.id):
                return False
            self.doing, self.ready_at = None, world.tick + 1
            return False
        self.doing.ticks -= 1
        if self.doing.ticks > 0:
            return False
        if self.doing.kind == "play":
            agent = world.agents[self.id]
            agent.playing = False
            world.emit(EventKind.STOP, self.id, item=agent.holding)
        self.doing = None
        return True

    def _stop(self, world: World) -> None:
        super()._stop(world)
        self.doing, self.ready_at = None, world.tick + 1

    # ----- deciding -------------------------------------------------------------------

    def _decide(self, world: World) -> None:
        now = world.tick * world.scenario.tick_seconds
        if self.last_decision is not None:
            elapsed = (now - self.last_decision) / self.table.decision_seconds
            if self.rng.random() < 1.0 - (1.0 - self.table.hazard) ** max(1.0, elapsed):
                self.preference = str(self.rng.choice(self.options))
        self.last_decision = now
        agent = world.agents[self.id]
        cell = self.table.cell_index[agent.cell]
        held = 0 if agent.holding is None else self.table.items.index(agent.holding) + 1
        goal = self.table.goals.index(self.preference)
        p = self.table.choice(goal, cell, held, self._world_belief(cell, agent.holding))
        action = int(self.rng.choice(len(p), p=p))
        self.decisions.append((world.tick, self.table.actions[action], float(p[action])))
        self._act(world, self.table.actions[action])

    def _world_belief(self, cell: int, holding: str | None) -> np.ndarray:
        """``(W,)`` the person's belief over the planner's worlds."""
        values = np.zeros((len(self.table.items), value_count(len(self.table.locations))))
        for k, item in enumerate(self.table.items):
            if item == holding:
                values[k, value_of(int(self.table.nearest[cell]), held=True)] = 1.0
            else:
                values[k, HELD if item in self.held_by_others else RESTING] = self.belief.of(item)
        return self.table.world_belief(values)

    def _act(self, world: World, action: str) -> None:
        agent = world.agents[self.id]
        ok = False
        if action in ("up", "down", "left", "right"):
            dc, dr = self.table.moves[("up", "down", "left", "right").index(action)]
            target = (agent.cell[0] + int(dc), agent.cell[1] + int(dr))
            ok = target in self.table.cell_index and world.plan_to(self.id, target)
            if ok:
                self.doing = Doing("move")
                return
        elif action.startswith("take:"):
            spot = world.location_at.get(agent.cell)
            item = world.items.get(action[5:])
            ok = spot is not None and item is not None and item.location == spot.id
            ok = ok and world.take(self.id, action[5:]) is None
        elif action == "drop":
            spot = world.location_at.get(agent.cell)
            ok = spot is not None and world.drop(self.id, spot.id) is None
        elif action == "play":
            ok = self._play(world)
            if ok:
                self._seen(world, world.tick)
                return
        elif action.startswith("use:"):
            ok = world.use(self.id, action[4:]) is None
        if ok:
            self._seen(world, world.tick)
            self.ready_at = world.tick + 1
            return
        self._stand(world)

    def _seen(self, world: World, tick: int) -> None:
        """The tracker sees a decision of this person at ``tick``."""
        self.seen_decision, self.stays = tick * world.scenario.tick_seconds, 0

    def _stand(self, world: World) -> None:
        """A Stay: stand still until the tracker reads it (module docstring), or, on a cell of
        the outside (where the tracker reads no waits), for at least ``Autonomy.wait_ticks``."""
        tick, d = world.scenario.tick_seconds, self.table.decision_seconds
        self.stays += 1
        if self.table.wait_decisions > 0 and self.seen_decision is not None:
            until = self.seen_decision + (self.table.wait_decisions - 1 + self.stays) * d
            ticks = max(1, math.ceil((until - world.tick * tick) / tick - 1e-6))
        else:  # the tracker reads no wait (it ignores them, or has seen no decision yet): one decision time
            ticks = math.ceil(d / tick - 1e-6)
        if world.region_of.get(world.agents[self.id].cell) in world.map.outside_regions:
            # an outside cell (not a door into it, which the tracker reads as inside)
            ticks = max(ticks, self._ticks(self.autonomy.wait_ticks))
        self.doing = Doing("stand", ticks)

    def _play(self, world: World) -> bool:
        agent = world.agents[self.id]
        spot = world.location_at.get(agent.cell)
        if agent.holding is None or spot is None or not spot.play:
            return False
        agent.playing = True
        world.emit(EventKind.PLAY, self.id, item=agent.holding, location=spot.id)
        self.doing = Doing("play", self._ticks(self.autonomy.play_ticks))
        return True
