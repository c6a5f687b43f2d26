"""Where a carried item counts as being: its carrier's location.

The nearest item location (by walking distance) of the carrier's region, or the nearest of
all locations when the region has none (a hall, a doorway, the outside). Engines, brains
and evaluators that report item locations use this one rule, so that "where is the ball"
has one answer while someone carries it.
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
