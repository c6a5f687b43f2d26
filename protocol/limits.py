"""The largest scene a toyroom engine serves and a brain accepts, stated once: sim2d's loader
refuses a map or scenario beyond them while reading its file (before building anything of
that size), and :func:`~protocol.scene_check.scene_problems` refuses such a scene at the
handshake. Each is far above anything bundled or generated (``toyroom bench``'s largest
house: 39 x 11 = 429 grid cells, 21 regions, 20 spots, 10 items, 9 agents).

The brain's own bound on its model's memory (which grows with cells, spots and items
together) is :data:`brain.model.size.MAX_MODEL_BYTES`.

The counts alone do not bound the scene's size on the wire: its visibility table lists, for
every walkable cell, the id of every spot seen from it, so an open 100 x 100 room with 200
spots of 64-character ids is 10,000 x 200 x 67 bytes, a 134 MB ``engine_info``. The encoded
scene is bounded too (:data:`MAX_SCENE_BYTES`), so that every scene within the limits fits
one frame of the WebSocket gateway (:data:`MAX_FRAME_BYTES`).
"""

from __future__ import annotations

import math

import msgspec

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

MAX_FRAME_BYTES = 16 * 1024 * 1024
"""The WebSocket gateway's largest frame (:mod:`toyroom.gateway`; 16 MiB): an engine behind it
answers the handshake with its whole ``engine_info`` in one frame."""
MAX_SCENE_BYTES = MAX_FRAME_BYTES - 1024 * 1024
"""The largest scene, encoded as JSON (15 MiB): the frame less 1 MiB for the rest of
``engine_info`` and the frame around it. The bundled scenes are 2 to 7 kB; an open 100 x 100
room fits with up to 22 spots of 64-character ids seen from every cell."""

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
    if not problems:
        problems += size_problems(scene)
    return problems


def size_problems(scene: Scene) -> list[str]:
    """One line naming the scene's encoded size, its visibility table's share and the limit,
    when the scene encoded as JSON is above :data:`MAX_SCENE_BYTES` (empty otherwise)."""
    size = len(msgspec.json.encode(scene))
    if size <= MAX_SCENE_BYTES:
        return []
    table = size - len(msgspec.json.encode(msgspec.structs.replace(scene, visibility=()))) + len(b"[]")
    return [
        f"scene: {size:,} bytes as JSON (its visibility table {table:,}: {len(scene.visibility):,} cells, "
        f"each listing the spots seen from it), above the limit of {MAX_SCENE_BYTES:,} bytes "
        f"(an engine_info must fit the WebSocket gateway's frame of {MAX_FRAME_BYTES:,} bytes)"
    ]
