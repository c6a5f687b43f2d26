"""The simulated world's state: agents' and items' bodies, who holds what, and the
actions every agent (scripted person or robot) performs on it. Events are collected per
tick; the physics moves bodies along planned paths of cells."""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field

from protocol import AgentKind, AgentState, Event, EventKind, GridCell, ItemState, Location
from protocol.carry import CarrierSight, carry_locations

from ..scenario.maps import GameMap
from ..scenario.scenario import Scenario
from .paths import path_to_any, shortest_path
from .physics import Physics
from .states import BodyStates
from .walls import wall_segments

PERSON_SPEED = 1.5
"""Walking speed of people and the robot, metres per second."""
ARRIVED = 1e-3
"""Distance (m) at which a body has reached a cell centre."""


@dataclass
class Agent:
    """An agent's mutable state besides its pymunk body."""

    id: str
    kind: AgentKind
    radius: float
    speed: float
    cell: GridCell
    region: str
    path: list[GridCell] = field(default_factory=list)
    holding: str | None = None
    playing: bool = False
    heading: float = 0.0


@dataclass
class Item:
    """Where an item is: resting at ``location``, or held by ``holder``."""

    id: str
    location: str | None = None
    holder: str | None = None


class World:
    """Bodies, ownership and actions; one instance per episode."""

    def __init__(self, scenario: Scenario, substeps: int = 5) -> None:
        self.scenario = scenario
        self.map: GameMap = scenario.map
        self.walkable = self.map.walkable
        self.region_of = self.map.region_of
        self.locations: dict[str, Location] = {loc.id: loc for loc in self.map.locations}
        self.location_at: dict[GridCell, Location] = {
            (loc.cell.col, loc.cell.row): loc for loc in self.map.locations
        }
        self.region_cells: dict[str, list[GridCell]] = {}
        for cell, region in sorted(self.region_of.items()):
            self.region_cells.setdefault(region, []).append(cell)
        self.nearest = carry_locations(self.map.scene((), ()))
        self.sight = CarrierSight(self.map.scene((), ()))  # who sees a carried item
        self.physics = Physics(
            wall_segments(self.walkable, self.map.cell_size), scenario.tick_seconds, substeps
        )
        self.tick = 0
        self.episode = 0
        self.events: list[Event] = []
        self.labels: set[tuple[str, str]] = set()
        self.agents: dict[str, Agent] = {}
        self.items: dict[str, Item] = {}
        self._states = BodyStates(self)
        """Each body's last state and what it was made of (:meth:`agent_states`)."""
        for setup in scenario.agents:
            radius = 0.3 if setup.kind is AgentKind.ROBOT else 0.25
            agent = Agent(setup.id, setup.kind, radius, PERSON_SPEED, setup.home, self.region_of[setup.home])
            self.agents[setup.id] = agent
            self.physics.add_agent(setup.id, self.map.centre(setup.home), radius, self._controller(setup.id))
        for item_setup in scenario.items:
            if item_setup.absent:  # not in the scene: no body, in no state
                continue
            item = Item(item_setup.id)
            self.items[item.id] = item
            if item_setup.at in self.agents:
                self.physics.add_item(item.id, self.map.centre(self.agents[item_setup.at].cell))
                item.holder = item_setup.at
                self.agents[item_setup.at].holding = item.id
                self.physics.attach(item.id, item_setup.at)
            else:
                loc = self.locations[item_setup.at]
                item.location = loc.id
                self.physics.add_item(item.id, self.map.centre((loc.cell.col, loc.cell.row)))

    # ----- events ---------------------------------------------------------------------

    def emit(self, kind: EventKind, actor: str, **fields: object) -> None:
        """Record an event of this tick."""
        self.events.append(
            Event(
                episode=self.episode,
                tick=self.tick,
                time=round(self.tick * self.scenario.tick_seconds, 9),
                kind=kind,
                actor=actor,
                **fields,  # type: ignore[arg-type]
            )
        )

    def complete(self, agent_id: str, label: str | None) -> None:
        """A scripted step is done: publish its label, if any."""
        if label is not None:
            self.labels.add((agent_id, label))
            self.emit(EventKind.WAYPOINT, agent_id, label=label, location=self.agents[agent_id].region)

    # ----- movement -------------------------------------------------------------------

    def plan_to(self, agent_id: str, goal: GridCell) -> bool:
        """Plan the shortest path to ``goal``; ``False`` when unreachable."""
        agent = self.agents[agent_id]
        path = shortest_path(self.walkable, agent.cell, goal)
        if path is None:
            return False
        agent.path = path
        return True

    def plan_to_region(self, agent_id: str, region: str) -> bool:
        """Plan the shortest path into ``region`` (its nearest cell)."""
        agent = self.agents[agent_id]
        path = path_to_any(self.walkable, agent.cell, self.region_cells[region])
        if path is None:
            return False
        agent.path = path
        return True

    def plan_to_region_cells(self, agent_id: str, cells: list[GridCell]) -> bool:
        """Plan the shortest path to the nearest of ``cells``."""
        agent = self.agents[agent_id]
        path = path_to_any(self.walkable, agent.cell, cells)
        if path is None:
            return False
        agent.path = path
        return True

    def arrived(self, agent_id: str) -> bool:
        """Whether the agent has no path left and stands at its cell's centre."""
        agent = self.agents[agent_id]
        if agent.path:
            return False
        x, y = self.physics.position(agent_id)
        cx, cy = self.map.centre(agent.cell)
        return math.hypot(cx - x, cy - y) < 0.05

    def stop(self, agent_id: str) -> None:
        """Drop the agent's path after the cell it is heading to."""
        agent = self.agents[agent_id]
        agent.path = agent.path[:1]

    def _controller(self, agent_id: str) -> Callable[[tuple[float, float], float], tuple[float, float]]:
        """Velocity control of one agent toward the next cell of its path (every substep)."""

        def velocity(position: tuple[float, float], sub_dt: float) -> tuple[float, float]:
            agent = self.agents[agent_id]
            x, y = position
            target = agent.path[0] if agent.path else agent.cell
            tx, ty = self.map.centre(target)
            dist = math.hypot(tx - x, ty - y)
            while dist < ARRIVED and agent.path:
                agent.path.pop(0)
                target = agent.path[0] if agent.path else target
                tx, ty = self.map.centre(target)
                dist = math.hypot(tx - x, ty - y)
            if dist < ARRIVED:
                return (0.0, 0.0)
            speed = min(agent.speed, dist / sub_dt)
            agent.heading = math.atan2(ty - y, tx - x)
            return ((tx - x) / dist * speed, (ty - y) / dist * speed)

        return velocity

    def step_physics(self) -> None:
        """One tick of physics, then :meth:`after_physics`. An agent standing still on its
        cell's centre with no path and empty hands skips its controller (which would answer
        zero every substep): most agents stand still most ticks."""
        for agent_id, agent in self.agents.items():
            self.physics.hold_still(agent_id, self._standing_still(agent))
        self.physics.step()
        self.after_physics()

    def _standing_still(self, agent: Agent) -> bool:
        if agent.path or agent.holding is not None or not self.physics.at_rest(agent.id):
            return False
        x, y = self.physics.position(agent.id)
        cx, cy = self.map.centre(agent.cell)
        return math.hypot(cx - x, cy - y) < ARRIVED

    def after_physics(self) -> None:
        """Update cells and regions from the bodies; emit enter/leave events."""
        for agent_id, agent in self.agents.items():
            x, y = self.physics.position(agent_id)
            cell = self.map.cell_at(x, y)
            if cell not in self.walkable:  # numerically on an edge: keep the last cell
                continue
            agent.cell = cell
            region = self.region_of.get(cell)
            if region is not None and region != agent.region:
                self.emit(EventKind.LEAVE, agent_id, location=agent.region)
                self.emit(EventKind.ENTER, agent_id, location=region)
                agent.region = region

    # ----- items ----------------------------------------------------------------------

    def within_reach(self, a: GridCell, b: GridCell) -> bool:
        """Same or 4-neighbouring cells."""
        return abs(a[0] - b[0]) + abs(a[1] - b[1]) <= 1

    def item_cell(self, item_id: str) -> GridCell:
        item = self.items[item_id]
        if item.holder is not None:
            return self.agents[item.holder].cell
        loc = self.locations[item.location or ""]
        return (loc.cell.col, loc.cell.row)

    def take(self, agent_id: str, item_id: str) -> str | None:
        """``agent_id`` takes a resting item within reach; the reason when it cannot."""
        agent, item = self.agents[agent_id], self.items[item_id]
        if agent.holding is not None:
            return f"hands full: {agent_id} holds '{agent.holding}'"
        if item.holder is not None:
            return f"item held by {item.holder}"
        if not self.within_reach(agent.cell, self.item_cell(item_id)):
            loc = self.locations[item.location or ""]
            return f"item not there: '{item_id}' is at {loc.id} ({loc.cell.col},{loc.cell.row})"
        location = item.location
        item.location, item.holder = None, agent_id
        agent.holding = item_id
        self.physics.attach(item_id, agent_id)
        self.emit(EventKind.TAKE, agent_id, item=item_id, location=location)
        return None

    def drop(self, agent_id: str, location_id: str) -> str | None:
        """Put the carried item down at ``location_id`` (within reach, and not full)."""
        agent = self.agents[agent_id]
        if agent.holding is None:
            return f"hands empty: {agent_id} holds nothing"
        loc = self.locations[location_id]
        if not self.within_reach(agent.cell, (loc.cell.col, loc.cell.row)):
            return f"out of reach: location {loc.id} is at ({loc.cell.col},{loc.cell.row})"
        resting = [i.id for i in self.items.values() if i.location == loc.id]
        if loc.capacity is not None and len(resting) >= loc.capacity:
            return f"location full: {loc.id} holds at most {loc.capacity} ({', '.join(resting)})"
        item = self.items[agent.holding]
        item.holder, item.location = None, loc.id
        agent.holding, agent.playing = None, False
        self.physics.put_down(item.id, self.map.centre((loc.cell.col, loc.cell.row)))
        self.emit(EventKind.DROP, agent_id, item=item.id, location=loc.id)
        return None

    def use(self, agent_id: str, item_id: str) -> str | None:
        """``agent_id`` uses ``item_id`` in place: it rests at the ``use`` location the agent
        stands on (or next to); the reason when it cannot."""
        agent, item = self.agents[agent_id], self.items.get(item_id)
        if item is None or item.location is None:
            return f"'{item_id}' is not resting anywhere"
        loc = self.locations[item.location]
        if not loc.use:
            return f"location {loc.id} is not a place to use things in"
        if not self.within_reach(agent.cell, (loc.cell.col, loc.cell.row)):
            return f"out of reach: location {loc.id} is at ({loc.cell.col},{loc.cell.row})"
        agent.playing = True
        self.emit(EventKind.USE, agent_id, item=item_id, location=loc.id)
        return None

    def hand_over(self, giver: str, receiver: str) -> None:
        """``giver``'s item goes into ``receiver``'s hands (both checked by the caller)."""
        item_id = self.agents[giver].holding
        assert item_id is not None
        self.agents[giver].holding = None
        self.agents[giver].playing = False
        self.agents[receiver].holding = item_id
        self.items[item_id].holder = receiver
        self.physics.attach(item_id, receiver)
        self.emit(EventKind.GIVE, giver, item=item_id, target=receiver)

    def swap(self, first: str, second: str) -> None:
        """Two agents exchange the items they hold (both hold one)."""
        a, b = self.agents[first], self.agents[second]
        item_a, item_b = a.holding, b.holding
        assert item_a is not None and item_b is not None
        a.holding, b.holding = item_b, item_a
        a.playing = b.playing = False
        self.items[item_a].holder, self.items[item_b].holder = second, first
        self.physics.attach(item_a, second)
        self.physics.attach(item_b, first)
        self.emit(EventKind.GIVE, first, item=item_a, target=second)
        self.emit(EventKind.GIVE, second, item=item_b, target=first)

    def item_location(self, item_id: str) -> str:
        """Where an item counts as being: its spot, or its carrier's location (the nearest
        spot of the carrier's region, or the nearest of all where the region has none)."""
        item = self.items[item_id]
        if item.holder is not None:
            return self.nearest[self.agents[item.holder].cell]
        return item.location or ""

    def percept(self, agent_id: str) -> tuple[tuple[str, ...], dict[str, str]]:
        """What ``agent_id`` sees: the visible locations, and where each item in view is."""
        cell = self.agents[agent_id].cell
        visible, seen = self.map.sees[cell], {}
        for item_id, item in self.items.items():
            carrier = self.agents[item.holder].cell if item.holder else None  # seen if the carrier is
            if self.sight.sees(cell, visible, carrier) if carrier else self.item_location(item_id) in visible:
                seen[item_id] = self.item_location(item_id)
        return visible, seen

    def play_spots(self) -> list[GridCell]:
        return [(loc.cell.col, loc.cell.row) for loc in self.map.locations if loc.play]

    # ----- state ----------------------------------------------------------------------

    def agent_states(self) -> tuple[AgentState, ...]:
        """Every agent's body now (:meth:`~sim2d.world.states.BodyStates.agents`)."""
        return self._states.agents()

    def item_states(self) -> tuple[ItemState, ...]:
        """Every item's body now (:meth:`~sim2d.world.states.BodyStates.items`)."""
        return self._states.items()
