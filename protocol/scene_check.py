"""Consistency checks of a :class:`~protocol.scene.Scene` beyond what its types enforce.

A scene can be well-typed and still broken: two regions claiming a cell, a door that
touches only one of the regions it joins, an item spot inside a wall, a room nobody can
walk to. :func:`scene_problems` lists every such problem, each naming the entry and what
is wrong; :func:`validate_scene` raises them together.
"""

from __future__ import annotations

from collections import Counter, deque
from collections.abc import Iterable

from .errors import ProtocolError
from .geometry import NEIGHBOURS, GridCell
from .limits import limit_problems
from .scene import Scene


class InvalidScene(ProtocolError):
    """A scene description that is well-typed but inconsistent.

    Attributes:
        problems: one line per problem, each naming the entry and what is wrong.
    """

    def __init__(self, problems: list[str], *, message_type: str | None = "engine_info") -> None:
        self.problems = problems
        listed = "; ".join(problems)
        super().__init__(
            f"{len(problems)} problem(s) in the scene: {listed}",
            message_type=message_type,
            field="$.scene",
        )


def _duplicates(ids: Iterable[str]) -> list[str]:
    return sorted(i for i, n in Counter(ids).items() if n > 1)


Cells = dict[GridCell, str]


def _id_problems(scene: Scene) -> list[str]:
    problems = ["regions: the scene has no region"] if not scene.regions else []
    for what, ids in (
        ("region/door", [r.id for r in scene.regions] + [d.id for d in scene.doors]),
        ("location", [loc.id for loc in scene.locations]),
        ("agent/item", [a.id for a in scene.agents] + [i.id for i in scene.items]),
    ):
        problems += [f"duplicate {what} id '{dup}'" for dup in _duplicates(ids)]
    return problems


def _region_cells(scene: Scene, problems: list[str]) -> Cells:
    """The region of every region cell (the first region to claim it), noting cells outside
    the grid or claimed twice in ``problems``."""
    region_of: Cells = {}
    for i, region in enumerate(scene.regions):
        for cell in region.cells:
            key = (cell.col, cell.row)
            if not (0 <= cell.col < scene.columns and 0 <= cell.row < scene.rows):
                problems.append(
                    f"regions[{i}] '{region.id}': cell ({cell.col},{cell.row}) is outside the "
                    f"{scene.columns}x{scene.rows} grid"
                )
            elif key in region_of and region_of[key] != region.id:
                problems.append(
                    f"regions[{i}] '{region.id}': cell ({cell.col},{cell.row}) already belongs "
                    f"to region '{region_of[key]}'"
                )
            region_of.setdefault(key, region.id)
    return region_of


def _door_problems(scene: Scene, region_of: Cells) -> list[str]:
    problems: list[str] = []
    region_ids = {r.id for r in scene.regions}
    for i, door in enumerate(scene.doors):
        key = (door.cell.col, door.cell.row)
        name = f"doors[{i}] '{door.id}'"
        if not (0 <= key[0] < scene.columns and 0 <= key[1] < scene.rows):
            problems.append(f"{name}: cell ({key[0]},{key[1]}) is outside the grid")
        if key in region_of:
            problems.append(
                f"{name}: cell ({key[0]},{key[1]}) lies inside region '{region_of[key]}'"
                " (a door cell belongs to no region)"
            )
        if door.joins[0] == door.joins[1]:
            problems.append(f"{name}: joins region '{door.joins[0]}' to itself")
        for joined in door.joins:
            if joined not in region_ids:
                problems.append(f"{name}: joins unknown region '{joined}'")
            elif not any(region_of.get((key[0] + dc, key[1] + dr)) == joined for dc, dr in NEIGHBOURS):
                problems.append(f"{name}: cell ({key[0]},{key[1]}) does not touch region '{joined}' it joins")
    return problems


def _location_problems(scene: Scene, region_of: Cells) -> list[str]:
    problems: list[str] = []
    region_ids = {r.id for r in scene.regions}
    for i, loc in enumerate(scene.locations):
        key = (loc.cell.col, loc.cell.row)
        name = f"locations[{i}] '{loc.id}'"
        if loc.region not in region_ids:
            problems.append(f"{name}: unknown region '{loc.region}'")
        elif region_of.get(key) != loc.region:
            where = f"region '{region_of[key]}'" if key in region_of else "a wall (not walkable)"
            problems.append(
                f"{name}: cell ({key[0]},{key[1]}) is in {where}, not in its region '{loc.region}'"
            )
    return problems


def _visibility_problems(scene: Scene, walkable: set[GridCell]) -> list[str]:
    problems: list[str] = []
    location_ids = {loc.id for loc in scene.locations}
    seen_cells: set[GridCell] = set()
    for i, vis in enumerate(scene.visibility):
        key = (vis.cell.col, vis.cell.row)
        name = f"visibility[{i}]"
        if key not in walkable:
            problems.append(f"{name}: cell ({key[0]},{key[1]}) is not walkable")
        if key in seen_cells:
            problems.append(f"{name}: cell ({key[0]},{key[1]}) has more than one entry")
        seen_cells.add(key)
        for loc_id in vis.locations:
            if loc_id not in location_ids:
                problems.append(f"{name}: cell ({key[0]},{key[1]}) names unknown location '{loc_id}'")
    missing = sorted(walkable - seen_cells)
    if missing:
        shown = ", ".join(f"({c},{r})" for c, r in missing[:5])
        more = f" and {len(missing) - 5} more" if len(missing) > 5 else ""
        problems.append(f"visibility: no entry for walkable cell(s) {shown}{more}")
    return problems


def _reach_problems(walkable: set[GridCell], region_of: Cells) -> list[str]:
    """Every walkable cell must be reachable from every other (through the doors)."""
    if not walkable:
        return []
    start = min(walkable)
    reached = {start}
    frontier = deque([start])
    while frontier:
        col, row = frontier.popleft()
        for dc, dr in NEIGHBOURS:
            nxt = (col + dc, row + dr)
            if nxt in walkable and nxt not in reached:
                reached.add(nxt)
                frontier.append(nxt)
    cut_off = sorted({region_of.get(c, "door") for c in walkable - reached})
    if not cut_off:
        return []
    first = region_of.get(start, "door")
    return [
        f"unreachable: no path from region '{first}' to region(s) " + ", ".join(f"'{r}'" for r in cut_off)
    ]


def scene_problems(scene: Scene) -> list[str]:
    """Every inconsistency in ``scene``, as readable lines; empty when the scene is sound. A
    scene beyond :mod:`protocol.limits` gets those problems alone (its cells are not walked)."""
    too_big = limit_problems(scene)
    if too_big:
        return too_big
    problems = _id_problems(scene)
    region_of = _region_cells(scene, problems)
    problems += _door_problems(scene, region_of)
    walkable = set(region_of) | {(d.cell.col, d.cell.row) for d in scene.doors}
    problems += _location_problems(scene, region_of)
    problems += _visibility_problems(scene, walkable)
    for i, agent in enumerate(scene.agents):
        key = (agent.home.col, agent.home.row)
        if key not in walkable:
            problems.append(f"agents[{i}] '{agent.id}': home cell ({key[0]},{key[1]}) is not walkable")
    return problems + _reach_problems(walkable, region_of)


def validate_scene(scene: Scene) -> Scene:
    """Return ``scene`` unchanged when sound; raise :class:`InvalidScene` listing every problem."""
    problems = scene_problems(scene)
    if problems:
        raise InvalidScene(problems)
    return scene
