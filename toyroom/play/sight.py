"""What one person sees, by the scene's own rules (pure: no I/O): the page of ``toyroom
play`` draws only this.

A person on cell ``c`` sees the item locations that the scene's visibility lists for ``c``,
so the regions of those locations, and the regions without locations (a hall, the outside)
that ``c`` is in or is a door of (:class:`protocol.carry.CarrierSight`'s ``open``). Agents
and carried items are seen where their carrier is seen (:meth:`CarrierSight.sees`), resting
items where their location is seen. What the person does not see now is drawn where they
last saw it (or were told it is): their own belief (:class:`Memory`), faded.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from protocol import AgentKind, Cell, ItemState, Scene, State
from protocol.carry import CarrierSight, carry_locations

from .keys import digit_keys

JsonDict = dict[str, Any]


@dataclass
class Memory:
    """Where the person believes each item is (location id), and since which tick."""

    places: dict[str, str] = field(default_factory=dict)
    ticks: dict[str, int] = field(default_factory=dict)

    def note(self, item: str, location: str, tick: int) -> None:
        """The person saw (or was told) ``item`` at ``location`` at ``tick``."""
        self.places[item] = location
        self.ticks[item] = tick


class Sight:
    """One person's view of a scene (the tables are built once per scene).

    Args:
        scene: the engine's scene.
        person: the person's agent id.
    """

    def __init__(self, scene: Scene, person: str) -> None:
        self.scene = scene
        self.person = person
        self.carrier = CarrierSight(scene)
        self.carried_at = carry_locations(scene)
        self.visible = {(v.cell.col, v.cell.row): frozenset(v.locations) for v in scene.visibility}
        self.region_of_location = {loc.id: loc.region for loc in scene.locations}
        self.location_cell = {loc.id: (loc.cell.col, loc.cell.row) for loc in scene.locations}
        self.names = {a.id: a.name or a.id for a in scene.agents} | {
            i.id: i.name or i.id for i in scene.items
        }
        self.robots = {a.id for a in scene.agents if a.kind is AgentKind.ROBOT}

    def regions_seen(self, cell: tuple[int, int]) -> frozenset[str]:
        """The regions a person on ``cell`` sees into."""
        spots = self.visible.get(cell, frozenset())
        return frozenset(self.region_of_location[s] for s in spots) | self.carrier.open.get(cell, frozenset())

    def _item_location(self, item: ItemState, cells: dict[str, tuple[int, int]]) -> str | None:
        if item.held_by is not None and item.held_by in cells:
            return self.carried_at.get(cells[item.held_by])
        return item.location

    def look(self, state: State, memory: Memory) -> JsonDict:
        """What the person sees in ``state`` (noting what they see in ``memory``), as the
        page's ``view`` message: regions and locations in sight, agents and items seen
        (positions in metres), and items remembered elsewhere (``faded``)."""
        cells = {a.id: (a.cell.col, a.cell.row) for a in state.agents}
        me = next((a for a in state.agents if a.id == self.person), None)
        if me is None:
            return {"type": "view", "tick": state.tick, "time": state.time, "missing": True}
        here = cells[self.person]
        spots = self.visible.get(here, frozenset())
        agents = [
            {
                "id": a.id,
                "name": self.names.get(a.id, a.id),
                "x": a.pose.x,
                "y": a.pose.y,
                "holding": a.holding,
                "playing": a.activity.value == "playing",
                "robot": a.id in self.robots,
                "you": a.id == self.person,
            }
            for a in state.agents
            if a.id == self.person or self.carrier.sees(here, spots, cells[a.id])
        ]
        seen_ids = {a["id"] for a in agents}
        items: list[JsonDict] = []
        for item in state.items:
            where = self._item_location(item, cells)
            seen = item.held_by in seen_ids if item.held_by is not None else where in spots
            if seen:
                if where is not None:
                    memory.note(item.id, where, state.tick)
                items.append(self._item(item.id, item.pose.x, item.pose.y, False, item.held_by))
        for item_id, where in memory.places.items():
            if item_id not in {i["id"] for i in items} and where in self.location_cell:
                col, row = self.location_cell[where]
                centre = self.scene.cell_centre(Cell(col=col, row=row))
                items.append(self._item(item_id, centre.x, centre.y, True, None))
        return {
            "type": "view",
            "tick": state.tick,
            "time": state.time,
            "done": state.done,
            "regions": sorted(self.regions_seen(here)),
            "locations": sorted(spots),
            "region": me.region,
            "holding": me.holding,
            "playing": me.activity.value == "playing",
            "agents": agents,
            "items": items,
        }

    def _item(self, item: str, x: float, y: float, faded: bool, held_by: str | None) -> JsonDict:
        return {
            "id": item,
            "name": self.names.get(item, item),
            "x": x,
            "y": y,
            "faded": faded,
            "held_by": held_by,
        }

    def layout(self, participant: str) -> JsonDict:
        """The page's ``scene`` message: the map to draw (cells, doors, locations with the
        key that walks there, names) and who the participant is."""
        scene = self.scene
        return {
            "type": "scene",
            "participant": participant,
            "person": self.person,
            "person_name": self.names.get(self.person, self.person),
            "columns": scene.columns,
            "rows": scene.rows,
            "cell_size": scene.cell_size,
            "origin": [scene.origin.x, scene.origin.y],
            "regions": [
                {
                    "id": r.id,
                    "name": r.name or r.id,
                    "kind": str(r.kind),
                    "cells": [[c.col, c.row] for c in r.cells],
                }
                for r in scene.regions
            ],
            "doors": [[d.cell.col, d.cell.row] for d in scene.doors],
            "locations": [
                {"id": loc.id, "region": loc.region, "cell": [loc.cell.col, loc.cell.row], "play": loc.play}
                for loc in scene.locations
            ],
            "goto_keys": goto_keys(scene),
        }


def goto_keys(scene: Scene) -> dict[str, str]:
    """The digit key that walks to each place: the locations, then the regions without one
    (``"1"`` the first, up to ``"9"``)."""
    with_spots = {loc.region for loc in scene.locations}
    targets = [loc.id for loc in scene.locations] + [r.id for r in scene.regions if r.id not in with_spots]
    return digit_keys(targets)
