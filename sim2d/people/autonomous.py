"""Autonomous simulated people: a true belief, a hidden preference, and a simple policy of
their own (not the brain's planner).

Each tick a person perceives (updating their :class:`~sim2d.people.belief.PersonBelief`), then
carries on with their current plan or makes a new one:

- wanting to leave (``out``): walk to the outside and wait there;
- holding the item they want: walk to the nearest play spot and play; after a while they
  may put it away somewhere and want something else;
- holding another item: put it down at the nearest spot;
- otherwise: walk to where they believe the item they want most likely is (a place found
  empty is crossed off by perception, and the next most likely is tried); take it; when
  they see someone else holding it, they wait, or wander to another room;
- now and then, with nothing in hand, they move an item that is not theirs to another spot
  (the mischief that creates false beliefs in others).

Their preference may change with a small probability per tick. They answer the robot: an
``inform`` replaces their belief about that item; a swap request is accepted when the item
offered is worth more to them than the one they hold.

Rich minds (:class:`~sim2d.scenario.autonomy.Autonomy`) are less tidy than the brain's model of them:
they forget (``forget_per_tick``), overlook items in view (``miss``: drawn once when an item comes
into view at a place, kept while it stays there), tell each other things (``hearsay_per_tick``,
:mod:`sim2d.people.hearsay`), look first where it is near (``search = "nearest"``), wander off
(``wander``) and change their minds on the way (``replan``). With every knob at its default
a person behaves exactly as the simple one does, draw for draw.

Every person drops a walk that their belief has made pointless (the item they are after seen
elsewhere, or gone from where they are heading: :func:`~sim2d.people.pursuit.pointless`) and decides
again, after a lag of their own (``Autonomy.replan_lag``). What they are doing is published
with their mind (:func:`~sim2d.people.pursuit.pursuit_of`).
"""

from __future__ import annotations

from collections import deque

import numpy as np

from protocol import AgentKind, EventKind, GridCell, NestedBelief, Pursuit, TrueMind

from ..scenario.autonomy import Autonomy
from ..scenario.scenario import AgentSetup
from ..world.world import World
from .belief import PersonBelief, item_beliefs
from .firstjobs import FirstJobs
from .nested import NestedMinds
from .pursuit import Primitive, Reconsider, pointless, pursuit_of

OUT = "out"


class AutonomousPerson:
    """A simulated person with a true mind (see the module docstring)."""

    def __init__(self, setup: AgentSetup, world: World, rng: np.random.Generator, autonomy: Autonomy) -> None:
        self.id = setup.id
        self.rng = rng
        self.autonomy = autonomy
        items = list(world.items)
        self.options = [*items, OUT]
        self.preference = setup.prefers if setup.prefers is not None else str(rng.choice(self.options))
        self.belief = PersonBelief(items, [loc.id for loc in world.map.locations])
        others = [a.id for a in world.agents.values() if a.kind is AgentKind.PERSON and a.id != self.id]
        self.nested = NestedMinds(self.id, others, items, [loc.id for loc in world.map.locations])
        """What this person believes the others believe (:mod:`sim2d.people.nested`)."""
        self.plan: deque[Primitive] = deque()
        self.current: Primitive | None = None
        self.left = 0
        self.started = False
        self.attention: dict[str, tuple[str, bool]] = {}
        """Item in view -> (where it is seen, whether the person noticed it there)."""
        self.carrying: dict[str, tuple[str, GridCell]] = {}
        """Item -> (who carries it, their cell), for the items seen carried by others."""
        self.first_jobs = FirstJobs(setup.jobs)
        """The first jobs of a task episode (:class:`~sim2d.scenario.jobs.Jobs`) yet to plan."""
        self.tells, self.tell_after = setup.jobs.tells, setup.jobs.tell_after
        self.overlooking = set(setup.jobs.overlooks)
        self.reconsider = Reconsider(autonomy.replan_lag)
        self.pursuit: Pursuit | None = None
        """What the person is doing, as of their last update."""
        self._mind: tuple[bytes, str, Pursuit | None, TrueMind] | None = None
        """The last :meth:`mind`, with the belief, preference and pursuit it was made of."""

    @property
    def finished(self) -> bool:
        """Autonomous people never finish: their episodes end at the scenario's time limit."""
        return False

    def mind(self) -> TrueMind:
        """The person's true belief, preference and pursuit (for ``engine/truth``); made again
        only when one of them has changed since the last call."""
        key = b"".join([self.belief.p.tobytes(), *(b.p.tobytes() for b in self.nested.beliefs.values())])
        last = self._mind
        if last is not None and last[0] == key and last[1] == self.preference and last[2] == self.pursuit:
            return last[3]
        nested = tuple(
            NestedBelief(agent=other, beliefs=item_beliefs(belief))
            for other, belief in self.nested.beliefs.items()
            if self.nested.started
        )
        mind = TrueMind(
            agent=self.id,
            beliefs=item_beliefs(self.belief),
            preference=self.preference,
            pursuit=self.pursuit,
            nested=nested,
        )
        self._mind = (key, self.preference, self.pursuit, mind)
        return mind

    # ----- the tick ---------------------------------------------------------------------

    def perceive(self, world: World) -> None:
        """Update the true belief on what the person sees now (idempotent within a tick)."""
        visible, seen = world.percept(self.id)
        self.belief.perceive(visible, seen, self._missed(world, seen), self._carried_off(world, seen))
        self._saw(world, seen)

    def _carried_off(self, world: World, seen: dict[str, str]) -> set[str]:
        """The items this person saw someone else carry at their last percept that they see
        no more, because the carrier moved (or put it down) out of sight; then remembers who
        carries what in view now."""
        lost = {
            item
            for item, (holder, cell) in self.carrying.items()
            if item not in seen and (world.items[item].holder != holder or world.agents[holder].cell != cell)
        }
        self.carrying = {
            item: (holder, world.agents[holder].cell)
            for item in seen
            if (holder := world.items[item].holder) is not None and holder != self.id
        }
        return lost

    def _saw(self, world: World, seen: dict[str, str]) -> None:
        """After perceiving the items in view, ``seen`` (where each is): nothing more here."""

    def _missed(self, world: World, seen: dict[str, str]) -> set[str]:
        """The items in view the person has not noticed (``Autonomy.miss``; their own is
        always noticed; drawn once per item and place it is seen at), and the items they
        overlook (:attr:`~sim2d.scenario.jobs.Jobs.overlooks`) until they stand where they believe one is."""
        if self.overlooking:
            cell = world.agents[self.id].cell
            spots = world.map.locations
            here = {loc.id for loc in spots if world.within_reach(cell, (loc.cell.col, loc.cell.row))}
            self.overlooking -= {item for item in self.overlooking if self.belief.most_likely(item) in here}
        overlooked = {item for item in seen if item in self.overlooking}
        if self.autonomy.miss <= 0:
            return overlooked
        own = world.agents[self.id].holding
        attention = {}
        for item, where in seen.items():
            before = self.attention.get(item)
            if item == own:
                attention[item] = (where, True)
            elif before is not None and before[0] == where:
                attention[item] = before
            else:
                attention[item] = (where, bool(self.rng.random() >= self.autonomy.miss))
        self.attention = attention
        return overlooked | {item for item, (_, noticed) in attention.items() if not noticed}

    def update(self, world: World) -> None:
        self.belief.forget(self.autonomy.forget_per_tick)
        self.perceive(world)
        busy = self.current is not None and (self.current.errand or self.current.do not in ("goto", "take"))
        if not busy and self.reconsider.check(pointless(self.pursuit, self.belief), world.tick, self.rng):
            self.current = None
            self.plan.clear()
        if (
            self.autonomy.replan > 0
            and self.current is not None
            and self.current.do == "goto"
            and not self.current.errand
            and self.rng.random() < self.autonomy.replan
        ):
            self.current = None
            self.plan.clear()
        if self.rng.random() < self.autonomy.switch:
            self.preference = str(self.rng.choice([o for o in self.options if o != self.preference]))
            if self.current is not None and self.current.do in ("play", "wait"):
                self._stop(world)
        if self.current is None and not self.plan:
            self._decide(world)
        if self.current is None and self.plan:
            self.current, self.started = self.plan.popleft(), False
        if self.current is not None:
            self._carry_on(world)
        self._note_pursuit(world)

    def _note_pursuit(self, world: World) -> None:
        steps = [self.current, *self.plan] if self.current is not None else list(self.plan)
        self.pursuit = pursuit_of(steps, world, world.agents[self.id].cell)

    def _stop(self, world: World) -> None:
        agent = world.agents[self.id]
        if agent.playing:
            agent.playing = False
            world.emit(EventKind.STOP, self.id, item=agent.holding)
        self.current = None
        self.plan.clear()

    def _carry_on(self, world: World) -> None:
        step = self.current
        assert step is not None
        agent = world.agents[self.id]
        if step.do == "goto":
            if not self.started:
                self.started = True
                if step.cell is None or not world.plan_to(self.id, step.cell):
                    self.current = None
                    return
            if world.arrived(self.id):
                self.current = None
            return
        if step.do in ("take", "drop"):
            if not world.arrived(self.id):
                return
            if step.do == "take" and step.item is not None:
                world.take(self.id, step.item)
            elif step.location is not None:
                world.drop(self.id, step.location)
            self.current = None
            return
        if not self.started:
            self.started, self.left = True, step.ticks
            if step.do == "play":
                if agent.holding is None:
                    self.current = None
                    return
                agent.playing = True
                spot = world.location_at.get(agent.cell)
                world.emit(EventKind.PLAY, self.id, item=agent.holding, location=spot.id if spot else None)
        self.left -= 1
        if self.left <= 0:
            if step.do == "play":
                agent.playing = False
                world.emit(EventKind.STOP, self.id, item=agent.holding)
                if (
                    self.rng.random() < self.autonomy.put_away
                ):  # done with it: put it away, want something else
                    spots = [loc for loc in world.map.locations if not loc.play]
                    if spots:
                        loc = spots[int(self.rng.integers(len(spots)))]
                        self.plan.extend(
                            [
                                Primitive("goto", cell=(loc.cell.col, loc.cell.row)),
                                Primitive("drop", location=loc.id),
                            ]
                        )
                        self.preference = str(self.rng.choice(self.options))
            self.current = None

    # ----- deciding -----------------------------------------------------------------------

    def _ticks(self, bounds: tuple[int, int]) -> int:
        return int(self.rng.integers(bounds[0], bounds[1] + 1))

    def _first_jobs(self, world: World) -> bool:
        """Plan a task episode's next first job, if one is left
        (:meth:`~sim2d.people.firstjobs.FirstJobs.next_steps`)."""
        steps = self.first_jobs.next_steps(world, self.id)
        self.plan.extend(steps)
        return bool(steps)

    def _decide(self, world: World) -> None:
        if self._first_jobs(world):
            return
        agent = world.agents[self.id]
        want = self.preference
        if agent.holding is None and self.rng.random() < self.autonomy.mischief and self._mischief(world):
            return
        if want == OUT:
            if world.map.regions and not self._outside(world):
                outside = [c for c, r in world.region_of.items() if r in world.map.outside_regions]
                if outside:
                    target = min(outside, key=lambda c: abs(c[0] - agent.cell[0]) + abs(c[1] - agent.cell[1]))
                    self.plan.append(Primitive("goto", cell=target))
                    return
            self.plan.append(Primitive("wait", ticks=self._ticks(self.autonomy.wait_ticks)))
            return
        if agent.holding == want:
            spots = world.play_spots()
            if spots:
                spot = min(spots, key=lambda c: abs(c[0] - agent.cell[0]) + abs(c[1] - agent.cell[1]))
                if agent.cell != spot:
                    self.plan.append(Primitive("goto", cell=spot))
            self.plan.append(Primitive("play", ticks=self._ticks(self.autonomy.play_ticks)))
            return
        if agent.holding is not None:
            loc = min(
                world.map.locations,
                key=lambda spot: abs(spot.cell.col - agent.cell[0]) + abs(spot.cell.row - agent.cell[1]),
            )
            self.plan.extend(
                [Primitive("goto", cell=(loc.cell.col, loc.cell.row)), Primitive("drop", location=loc.id)]
            )
            return
        item = world.items[want]
        visible, _ = world.percept(self.id)
        if item.holder is not None and world.item_location(want) in visible:
            self.plan.append(Primitive("wait", ticks=self._ticks(self.autonomy.wait_ticks)))  # occupied: wait
            return
        believed = self._where_to_look(world, want)
        if believed is None:
            self.plan.append(Primitive("wait", ticks=self._ticks(self.autonomy.wait_ticks)))
            return
        loc = world.locations[believed]
        if self.autonomy.wander > 0 and self.rng.random() < self.autonomy.wander:
            cells = sorted(world.region_of)
            self.plan.append(Primitive("goto", cell=cells[int(self.rng.integers(len(cells)))]))
        self.plan.extend([Primitive("goto", cell=(loc.cell.col, loc.cell.row)), Primitive("take", item=want)])

    def _where_to_look(self, world: World, item: str) -> str | None:
        """The place to look for ``item`` first (``Autonomy.search``)."""
        if self.autonomy.search == "likely":
            return self.belief.most_likely(item)
        row = self.belief.of(item)
        if row.max() <= 0:
            return None
        col, rowx = world.agents[self.id].cell
        candidates = [loc for loc, p in zip(self.belief.locations, row, strict=True) if p >= 0.5 * row.max()]
        return min(
            candidates,
            key=lambda loc: (
                abs(world.locations[loc].cell.col - col) + abs(world.locations[loc].cell.row - rowx)
            ),
        )

    def _outside(self, world: World) -> bool:
        return world.agents[self.id].region in world.map.outside_regions

    def _mischief(self, world: World) -> bool:
        """Plan to move an item that is not this person's wish from a spot in view to another."""
        visible, seen = world.percept(self.id)
        candidates = [
            i for i, where in seen.items() if i != self.preference and world.items[i].holder is None
        ]
        others = [loc for loc in world.map.locations if loc.id not in visible]
        if not candidates or not others:
            return False
        item = candidates[int(self.rng.integers(len(candidates)))]
        src = world.locations[world.items[item].location or ""]
        dst = others[int(self.rng.integers(len(others)))]
        self.plan.extend(
            [
                Primitive("goto", cell=(src.cell.col, src.cell.row)),
                Primitive("take", item=item),
                Primitive("goto", cell=(dst.cell.col, dst.cell.row)),
                Primitive("drop", location=dst.id),
            ]
        )
        return True

    # ----- reactions to the robot -----------------------------------------------------------

    def on_given(self, world: World) -> None:
        self._stop(world)

    def on_informed(self, world: World, item: str, location: str) -> None:
        """Take it in; go for it at once if it is what they want (after an errand under way)."""
        self.belief.told(item, location)
        busy = (self.current is not None and self.current.errand) or any(p.errand for p in self.plan)
        if item == self.preference and world.agents[self.id].holding is None and not busy:
            self._stop(world)

    def says_wanted(self, world: World, item: str | None) -> tuple[str | None, bool] | None:
        """Truthfully, when free; busy (carrying something, playing, or on an errand), no
        answer at all with chance ``Autonomy.silent`` (drawn per question)."""
        agent = world.agents[self.id]
        errand = (self.current is not None and self.current.errand) or any(p.errand for p in self.plan)
        busy = agent.holding is not None or agent.playing or errand
        if busy and self.rng.random() < self.autonomy.silent:
            return None
        wanted = None if self.preference == OUT else self.preference
        if item is not None:
            return item, item == wanted
        return (wanted, True) if wanted is not None else (None, False)

    def answer(self, world: World, item: str, offer: str | None = None) -> bool:
        """Swap when the offer is worth more to them than what they hold."""

        def worth(thing: str | None) -> int:
            return 1 if thing is not None and thing == self.preference else 0

        return world.agents[self.id].holding == item and worth(offer) > worth(item)

    def on_handed_over(self, world: World) -> None:
        self._stop(world)
