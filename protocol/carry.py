"""Where a carried item counts as being: its carrier's location.

The nearest item location (by walking distance) of the carrier's region, or the nearest of
all locations when the region has none (a hall, a doorway, the outside). Engines, brains
and evaluators that report item locations use this one rule, so that "where is the ball"
has one answer while someone carries it. Who *sees* a carried item is another matter: only
those who see its carrier (:class:`CarrierSight`), so an item carried through a hall is not
seen from a room whose location it counts at.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Collection, Iterable

from .geometry import NEIGHBOURS, GridCell
from .scene import Scene


def walking_distances(walkable: Collection[GridCell], starts: Iterable[GridCell]) -> dict[GridCell, int]:
    """Walking distance, in cells, from the nearest of ``starts`` to every walkable cell it
    reaches (a breadth-first search from all of them at once)."""
    seen = dict.fromkeys(starts, 0)
    queue = deque(seen)
    while queue:
        cell = queue.popleft()
        for dc, dr in NEIGHBOURS:
            nxt = (cell[0] + dc, cell[1] + dr)
            if nxt in walkable and nxt not in seen:
                seen[nxt] = seen[cell] + 1
                queue.append(nxt)
    return seen


def location_distances(scene: Scene) -> dict[str, dict[GridCell, int]]:
    """Walking distance, in cells, from each location to every walkable cell it reaches."""
    walkable = scene.walkable()
    return {loc.id: walking_distances(walkable, [(loc.cell.col, loc.cell.row)]) for loc in scene.locations}


def carry_locations(scene: Scene) -> dict[GridCell, str]:
    """For every walkable cell, the location id an item carried there counts as being at."""
    region_of = {(c.col, c.row): r.id for r in scene.regions for c in r.cells}
    order = [loc.id for loc in scene.locations]
    distance = location_distances(scene)
    out: dict[GridCell, str] = {}
    for cell in scene.walkable():
        own = [loc.id for loc in scene.locations if loc.region == region_of.get(cell)]
        pool = own or order
        if pool:
            out[cell] = min(pool, key=lambda lid: (distance[lid].get(cell, 1 << 30), order.index(lid)))
    return out


class CarrierSight:
    """Who sees someone carrying an item: a carried item is perceived only where its
    carrier is seen, by the scene's visibility.

    - A carrier in a region with locations is seen from every cell whose visibility lists
      the location the item counts at (:func:`carry_locations`, a location of that region).
    - A carrier on a door cell is seen from the cells that see its carry location when that
      location is in a region the door joins, and from the regions without locations the
      door joins.
    - A carrier in a region without locations (a hall, the outside) is seen only from that
      region and from the doors that join it: no location there says who else sees it, and
      the location the item counts at is elsewhere, so seeing that location shows nothing.

    A person also sees a carrier on their own cell. Attributes (per walkable cell):
    ``spot``: the carry location whose sight shows a carrier there (absent: none);
    ``open``: the regions without locations that the cell is in or is a door of.
    """

    def __init__(self, scene: Scene) -> None:
        region_of = {(c.col, c.row): r.id for r in scene.regions for c in r.cells}
        joins = {(d.cell.col, d.cell.row): set(d.joins) for d in scene.doors}
        with_spots = {loc.region for loc in scene.locations}
        region_at = {loc.id: loc.region for loc in scene.locations}
        self.spot: dict[GridCell, str] = {}
        self.open: dict[GridCell, frozenset[str]] = {}
        carried = carry_locations(scene)
        for cell in scene.walkable():
            areas = joins.get(cell) or ({region_of[cell]} if cell in region_of else set())
            self.open[cell] = frozenset(a for a in areas if a not in with_spots)
            where = carried.get(cell)
            if where is not None and region_at.get(where) in areas:
                self.spot[cell] = where

    def sees(self, viewer: GridCell, visible: Collection[str], carrier: GridCell) -> bool:
        """Whether a person on ``viewer``, who sees the locations ``visible``, sees someone
        carrying an item on ``carrier``."""
        spot = self.spot.get(carrier)
        return (
            viewer == carrier
            or (spot is not None and spot in visible)
            or not self.open.get(viewer, frozenset()).isdisjoint(self.open.get(carrier, frozenset()))
        )
