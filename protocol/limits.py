"""The largest scene a toyroom engine serves and a brain accepts, stated once: sim2d's loader
refuses a map or scenario beyond them while reading its file (before building anything of
that size), and :func:`~protocol.scene_check.scene_problems` refuses such a scene at the
handshake. Each is far above anything bundled or generated (``toyroom bench``'s largest
house: 39 x 11 = 429 grid cells, 21 regions, 20 spots, 10 items, 9 agents).

The brain's own bound on its model's memory (which grows with cells, spots and items
together) is :data:`brain.model.size.MAX_MODEL_BYTES`.
"""

from __future__ import annotations

import math

from .scene import Scene

MAX_GRID_CELLS = 10_000
"""``columns x rows`` (a 100 x 100 grid). An open room of that size: sim2d builds it in about
2 s, its handshake carries about 750 KB (a visibility entry per cell), and the brain's planner
takes about 6 s on it, a time growing faster than the cells (29 s at 40,000); a 1000 x 997
room took sim2d over 60 s to start, and 100000 x 99995 ran it out of memory."""
MAX_REGIONS = 1_000
"""Regions (rooms) of a scene: each is at least one cell, and doors join them."""
MAX_LOCATIONS = 200
"""Item spots (``locations``): an item has ``2 x spots`` values in the brain's model."""
MAX_ITEMS = 100
"""Items: the brain's model grows as the square of the items (one plan per preference, an
action per item), and exponentially in its exact form."""
MAX_AGENTS = 100
"""Agents (people and robots): the brain tracks every person, and each pair for nested beliefs."""
MAX_CELL_SIZE = 1_000.0
"""The largest cell side (m); with the grid limit, coordinates stay far inside float64."""

LIMITS = {
    "grid cells (columns x rows)": MAX_GRID_CELLS,
    "regions": MAX_REGIONS,
    "locations": MAX_LOCATIONS,
    "items": MAX_ITEMS,
    "agents": MAX_AGENTS,
}
"""Every count limit by what it counts, as :func:`limit_problems` names them."""


def over_limit(what: str, count: int, limit: int) -> str | None:
    """``what: N, above the limit of M`` when ``count > limit``, else ``None``."""
    return f"{what}: {count:,}, above the limit of {limit:,}" if count > limit else None


def limit_problems(scene: Scene) -> list[str]:
    """Every limit ``scene`` exceeds, one line each naming the limit and the value (empty when
    none): checked before the scene's cells are looked at one by one."""
    counts = {
        "grid cells (columns x rows)": scene.columns * scene.rows,
        "regions": len(scene.regions),
        "locations": len(scene.locations),
        "items": len(scene.items),
        "agents": len(scene.agents),
    }
    problems = [p for what, n in counts.items() if (p := over_limit(what, n, LIMITS[what])) is not None]
    if not (math.isfinite(scene.cell_size) and scene.cell_size <= MAX_CELL_SIZE):
        problems.append(f"cell_size: {scene.cell_size} m, not a finite size of at most {MAX_CELL_SIZE:g} m")
    return problems
