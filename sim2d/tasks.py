"""Task episodes (``--kind tasks``): the two people of an episode built around one of the
robot's jobs (:data:`TASKS`), as ``[[agents]]`` lines of the scenario file.

The owner of the item a task is about starts beside it and knows where it is (``knows``:
they left it there, whatever the episode's minds), then goes on an errand outside. In
``moved`` and ``hidden`` the other person moves the item while the owner is away, timed to
land shortly before the owner is back (``move_after``, from walking times on the map): a
false belief the owner acts on as soon as they return, which the robot can put right only
if it notices.
"""

from __future__ import annotations

import math

import numpy as np

from protocol import GridCell, Location
from protocol.carry import walking_distances

from .maps import GameMap
from .world import PERSON_SPEED

TASKS = ("moved", "hidden", "contested", "seen")
"""The jobs task episodes are built around, in turn by seed: ``moved`` (shortly before its owner
comes back from an errand, someone moves the item they will come back for to a spot out of
their view), ``hidden`` (the same, to the spot the owner's search reaches last: where they
will not look), ``contested`` (both people want the same item) and ``seen`` (Sally-Anne's
true-belief control: the owner watches the item being moved to a spot in view, then goes on
the errand; putting it back would mislead them)."""

ERRAND_TICKS = (80, 200)
"""How long the owner's errand keeps them outside (ticks, drawn uniformly)."""
LEAD_TICKS = (10, 60)
"""How long before the owner starts back from the errand the moved item lands (ticks, drawn
uniformly): shortly before they come back for it."""
HANDLING_TICKS = 10
"""Ticks a take and a drop add to the mover's walk (a margin, not a measurement)."""


def task_of(seed: int) -> str:
    """The job a task episode of ``seed`` is built around."""
    return TASKS[seed % len(TASKS)]


def ticks_per_cell(game_map: GameMap, tick_seconds: float) -> int:
    """Ticks a person takes to walk one cell (rounded up)."""
    return math.ceil(game_map.cell_size / PERSON_SPEED / tick_seconds)


def search_order(game_map: GameMap, start: Location, search: str) -> list[Location]:
    """The spots a person who finds ``start`` empty tries next, in order, for want of any
    better clue: the locations' own order (``search = "likely"``: ties go to the first), or
    the nearest spot each time (``"nearest"``, by walking distance)."""
    visible = game_map.sees.get(_cell(start), ())
    rest = [loc for loc in game_map.locations if loc.id != start.id and loc.id not in visible]
    if search != "nearest":
        return rest
    order, here = [], start
    while rest:
        far = walking_distances(game_map.walkable, [_cell(here)])
        here = min(rest, key=lambda loc: (far.get(_cell(loc), 10**6), loc.id))
        rest.remove(here)
        order.append(here)
    return order


def _cell(loc: Location) -> GridCell:
    return (loc.cell.col, loc.cell.row)


def task_agents(
    game_map: GameMap,
    placed: dict[str, str],
    homes: list[GridCell],
    seed: int,
    *,
    tick_seconds: float = 0.1,
    search: str = "likely",
) -> list[str]:
    """The two people of a task episode, as ``[[agents]]`` lines (the first item is the one
    the task is about; ``homes``: cells to start from when the task does not fix one;
    ``search``: how the episode's people look for things, for ``hidden``)."""
    rng = np.random.default_rng([seed, 2])
    task, items = task_of(seed), list(placed)
    wanted = items[0]
    spot = next(loc for loc in game_map.locations if loc.id == placed[wanted])
    if task == "contested":
        return [
            line
            for person, home in zip(("A1", "A2"), homes[:2], strict=True)
            for line in person_lines(person, home, f'prefers = "{wanted}"')
        ]
    region = game_map.region_of[_cell(spot)]
    spots = {_cell(loc) for loc in game_map.locations}
    cells = sorted(
        c for c, r in game_map.region_of.items() if r == region and c not in spots and c != homes[2]
    )
    owner_home = cells[int(rng.integers(len(cells)))] if cells else homes[0]
    seen = set(game_map.sees.get(owner_home, ())) | {spot.id}
    unseen = [loc for loc in game_map.locations if loc.id not in seen] or [
        loc for loc in game_map.locations if loc.id != spot.id
    ]
    in_view = [loc for loc in game_map.locations if loc.id in seen and loc.id != spot.id]
    errand = int(rng.integers(ERRAND_TICKS[0], ERRAND_TICKS[1] + 1))
    owner = [f'prefers = "{wanted}"', f"errand = {errand}", f'knows = ["{wanted}"]']
    mover_home = next(h for h in homes if h != owner_home)
    if task == "seen" and in_view:
        target = in_view[int(rng.integers(len(in_view)))]
        owner.append(f"errand_after = {int(rng.integers(150, 251))}")
        after = 0
    else:
        order = [loc for loc in search_order(game_map, spot, search) if loc in unseen]
        target = (order or unseen)[-1] if task == "hidden" else unseen[int(rng.integers(len(unseen)))]
        lead = int(rng.integers(LEAD_TICKS[0], LEAD_TICKS[1] + 1))
        after = move_after(game_map, owner_home, mover_home, spot, target, errand, lead, tick_seconds)
    other = items[1] if len(items) > 1 else "out"
    mover = [f'prefers = "{other}"', f'move = ["{wanted}", "{target.id}"]']
    return [
        *person_lines("A1", owner_home, *owner),
        *person_lines("A2", mover_home, *mover, *([f"move_after = {after}"] if after else [])),
    ]


def move_after(
    game_map: GameMap,
    owner_home: GridCell,
    mover_home: GridCell,
    spot: Location,
    target: Location,
    errand: int,
    lead: int,
    tick_seconds: float,
) -> int:
    """Ticks the mover waits so that the item lands at ``target`` about ``lead`` ticks before
    the owner, after ``errand`` ticks outside, starts back; never taken before the owner is
    outside (so they do not see it go). From walking distances on the map."""
    tpc = ticks_per_cell(game_map, tick_seconds)
    outside = [c for c, r in game_map.region_of.items() if r in game_map.outside_regions]
    from_home = walking_distances(game_map.walkable, [owner_home])
    walk_out = min((from_home[c] for c in outside if c in from_home), default=0)
    from_spot = walking_distances(game_map.walkable, [_cell(spot)])
    to_spot = from_spot.get(mover_home, 0)
    carry = tpc * (to_spot + from_spot.get(_cell(target), 0)) + HANDLING_TICKS
    earliest = max(tpc * (walk_out - to_spot), 0)
    return max(tpc * walk_out + errand - lead - carry, earliest)


def person_lines(person: str, home: GridCell, *extra: str) -> list[str]:
    return [
        "[[agents]]",
        f'id = "{person}"',
        'kind = "person"',
        "autonomous = true",
        f"home = [{home[0]}, {home[1]}]",
        *extra,
        "",
    ]
