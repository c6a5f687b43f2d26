"""Maps as data: rooms made of cell rectangles, one-cell doors, item spots, visibility
groups and home cells, read from ``<name>.map.toml`` and checked.

A map turns into the protocol's :class:`~protocol.Scene`, whose visibility is given per
cell: a cell of region R sees the spots of the regions its visibility group names; a door
cell sees the spots of both regions it joins.
"""

from __future__ import annotations

import tomllib
from collections.abc import Collection
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from bridge.flags import open_regular
from protocol import (
    MAX_CELL_SIZE,
    MAX_GRID_CELLS,
    MAX_LOCATIONS,
    MAX_REGIONS,
    NEIGHBOURS,
    AgentKind,
    AgentSpec,
    Cell,
    Door,
    GridCell,
    ItemSpec,
    Location,
    Region,
    RegionKind,
    Scene,
    Vec2,
    Visibility,
    scene_problems,
)
from protocol.bundled import bundled_dir

from ..errors import ScenarioError
from .numbers import integer, real
from .tables import (
    DOOR_KEYS,
    LOCATION_KEYS,
    MAP_KEYS,
    REGION_KEYS,
    VISIBILITY_KEYS,
    check_keys,
    entry_of,
    table_id,
    tables,
)

SCENARIO_DIR = bundled_dir("sim2d", "scenarios")
"""Where the bundled maps (``*.map.toml``) and scenarios (``*.toml``) live."""


@dataclass(frozen=True)
class GameMap:
    """A checked map. Cells are ``(col, row)`` tuples; sizes in metres."""

    name: str
    path: Path
    cell_size: float
    columns: int
    rows: int
    regions: tuple[Region, ...]
    doors: tuple[Door, ...]
    locations: tuple[Location, ...]
    sees: dict[GridCell, tuple[str, ...]]
    """Per walkable cell, the location ids visible from it."""
    homes: dict[str, GridCell]

    @property
    def region_of(self) -> dict[GridCell, str]:
        """Region id of every region cell (door cells are absent)."""
        return {(c.col, c.row): r.id for r in self.regions for c in r.cells}

    @property
    def outside_regions(self) -> set[str]:
        """Ids of the regions of kind ``outside``."""
        return {r.id for r in self.regions if r.kind == RegionKind.OUTSIDE}

    @property
    def walkable(self) -> frozenset[GridCell]:
        """Region cells and door cells."""
        return frozenset(self.region_of) | {(d.cell.col, d.cell.row) for d in self.doors}

    def location(self, location_id: str) -> Location:
        """The location with this id (``KeyError`` when unknown)."""
        for loc in self.locations:
            if loc.id == location_id:
                return loc
        raise KeyError(location_id)

    def centre(self, cell: GridCell) -> tuple[float, float]:
        """World coordinates (m) of a cell's centre; the origin is the grid's corner."""
        return ((cell[0] + 0.5) * self.cell_size, (cell[1] + 0.5) * self.cell_size)

    def cell_at(self, x: float, y: float) -> GridCell:
        """The cell containing world point ``(x, y)`` (m)."""
        return (int(x // self.cell_size), int(y // self.cell_size))

    def scene(self, agents: tuple[AgentSpec, ...], items: tuple[ItemSpec, ...]) -> Scene:
        """The protocol scene of this map with the given agents and items."""
        visibility = tuple(
            Visibility(cell=Cell(*cell), locations=self.sees[cell]) for cell in sorted(self.sees)
        )
        return Scene(
            name=self.name,
            cell_size=self.cell_size,
            origin=Vec2(0.0, 0.0),
            columns=self.columns,
            rows=self.rows,
            regions=self.regions,
            doors=self.doors,
            locations=self.locations,
            visibility=visibility,
            agents=agents,
            items=items,
        )


def _is_int(value: Any) -> bool:
    return isinstance(value, int) and not isinstance(value, bool)


def parse_cell(value: Any, path: Path, entry: str) -> GridCell:
    """A ``[col, row]`` cell read from a scenario file (``entry`` of ``path``, for the error)."""
    if (
        not isinstance(value, list)
        or len(value) != 2
        or not all(isinstance(v, int) and not isinstance(v, bool) for v in value)
    ):
        raise ScenarioError(path, entry, f"expected a cell [col, row] of two integers, got {value!r}")
    return (value[0], value[1])


def _str(table: dict[str, Any], key: str, path: Path, entry: str) -> str:
    value = table.get(key)
    if not isinstance(value, str) or not value:
        raise ScenarioError(path, entry, f"expected a non-empty string '{key}', got {value!r}")
    return value


def read_toml(path: Path) -> dict[str, Any]:
    """Read a TOML file; a syntax error names the file and line, and a file that is not a
    regular one (a FIFO, a folder) is refused without waiting on it."""
    try:
        with open_regular(path) as handle:
            return tomllib.load(handle)
    except FileNotFoundError:
        if path.parent == SCENARIO_DIR:  # a bundled name that is not: say which ones are
            kind, suffix = ("map", ".map.toml") if path.name.endswith(".map.toml") else ("scenario", ".toml")
            names = (p.name.removesuffix(suffix) for p in SCENARIO_DIR.glob("*.toml"))
            known = ", ".join(sorted(n for n in names if "." not in n))  # not the other kind's
            entry = f"{kind} '{path.name.removesuffix(suffix)}'"
            raise ScenarioError(path, entry, f"not bundled; known: {known} (or give a .toml file)") from None
        raise ScenarioError(path, "", "no such file") from None
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as err:
        raise ScenarioError(path, "", f"not valid TOML: {err}") from None
    except RecursionError:
        raise ScenarioError(path, "", "not valid TOML: nested too deep to read") from None
    except OSError as err:
        raise ScenarioError(path, "", f"cannot read it: {err.strerror or err}") from None


def map_path(name_or_path: str) -> Path:
    """A bundled map's file for a name (``paper``), or the path itself."""
    candidate = Path(name_or_path)
    if candidate.suffix == ".toml":
        return candidate
    return SCENARIO_DIR / f"{name_or_path}.map.toml"


def _grid(data: dict[str, Any], path: Path) -> tuple[float, int, int]:
    """``cell_size`` (m), ``columns`` and ``rows`` of a map file, the grid within
    :data:`protocol.MAX_GRID_CELLS` (checked before any cell is built)."""
    cell_size = real(data.get("cell_size", 1.0), path, "cell_size", "cell_size", MAX_CELL_SIZE)
    if "columns" not in data or "rows" not in data:
        raise ScenarioError(path, "", "expected integers columns and rows")
    columns = integer(data["columns"], path, "columns", "columns")
    rows = integer(data["rows"], path, "rows", "rows")
    if columns * rows > MAX_GRID_CELLS:
        problem = (
            f"{columns:,} x {rows:,} = {columns * rows:,} grid cells, above the limit of {MAX_GRID_CELLS:,}"
        )
        raise ScenarioError(path, "columns, rows", problem)
    return cell_size, columns, rows


def _rect_cells(rect: Any, path: Path, entry: str, columns: int, rows: int) -> list[GridCell]:
    """The cells of one ``[col, row, width, height]`` rectangle, each inside the grid."""
    if not (isinstance(rect, list) and len(rect) == 4 and all(_is_int(v) for v in rect)):
        raise ScenarioError(path, entry, f"expected rects of [col, row, width, height], got {rect!r}")
    col, row, width, height = rect
    if width < 1 or height < 1:
        raise ScenarioError(path, entry, f"rect {rect} has no cells")
    cells = [(c, r) for c in range(col, col + width) for r in range(row, row + height)]
    for c, r in cells:
        if not (0 <= c < columns and 0 <= r < rows):
            raise ScenarioError(path, entry, f"cell ({c},{r}) is outside the {columns}x{rows} grid")
    return cells


def _region(
    table: dict[str, Any], i: int, path: Path, grid: tuple[int, int], region_of: dict[GridCell, str]
) -> Region:
    """``regions[i]``, its cells added to ``region_of`` (each cell in one region only)."""
    table = check_keys(table, REGION_KEYS, path, entry_of(table, "regions", i))
    rid = table_id(table, path, f"regions[{i}]")
    entry = f"regions[{i}] '{rid}'"
    try:
        kind = RegionKind(table.get("kind", "room"))
    except ValueError:
        known = ", ".join(k.value for k in RegionKind)
        raise ScenarioError(path, entry, f"unknown kind {table.get('kind')!r}; known: {known}") from None
    cells: list[GridCell] = []
    for rect in table.get("rects", []):
        for c, r in _rect_cells(rect, path, entry, *grid):
            if (c, r) in region_of:
                raise ScenarioError(path, entry, f"cell ({c},{r}) already belongs to '{region_of[(c, r)]}'")
            region_of[(c, r)] = rid
            cells.append((c, r))
    if not cells:
        raise ScenarioError(path, entry, "a region needs at least one cell ('rects')")
    return Region(id=rid, kind=kind, cells=tuple(Cell(*c) for c in cells), name=str(table.get("name", "")))


def _regions(
    data: dict[str, Any], path: Path, grid: tuple[int, int]
) -> tuple[list[Region], dict[GridCell, str]]:
    """Every region, and the region of every region cell."""
    region_of: dict[GridCell, str] = {}
    regions = [
        _region(table, i, path, grid, region_of)
        for i, table in enumerate(tables(data, "regions", path, MAX_REGIONS))
    ]
    region_ids = [r.id for r in regions]
    if not regions:
        raise ScenarioError(path, "regions", "the map has no region")
    if len(set(region_ids)) != len(region_ids):
        raise ScenarioError(path, "regions", f"duplicate region ids in {region_ids}")
    return regions, region_of


def _door(
    table: dict[str, Any], i: int, path: Path, region_of: dict[GridCell, str], region_ids: list[str]
) -> Door:
    """``doors[i]``: a wall cell touching both the regions it joins."""
    table = check_keys(table, DOOR_KEYS, path, entry_of(table, "doors", i))
    did = table_id(table, path, f"doors[{i}]")
    entry = f"doors[{i}] '{did}'"
    cell = parse_cell(table.get("cell"), path, entry)
    joins = table.get("joins")
    if not (isinstance(joins, list) and len(joins) == 2 and all(isinstance(j, str) for j in joins)):
        raise ScenarioError(path, entry, f"expected joins = [region, region], got {joins!r}")
    for joined in joins:
        if joined not in region_ids:
            raise ScenarioError(path, entry, f"unknown room '{joined}'; rooms: {', '.join(region_ids)}")
    if cell in region_of:
        raise ScenarioError(path, entry, f"cell {cell} is inside room '{region_of[cell]}', not in a wall")
    touching = {region_of.get((cell[0] + dc, cell[1] + dr)) for dc, dr in NEIGHBOURS}
    for joined in joins:
        if joined not in touching:
            raise ScenarioError(
                path,
                entry,
                f"door not on a wall shared by {joins[0]} and {joins[1]}: cell {cell} "
                f"does not touch '{joined}'",
            )
    return Door(id=did, cell=Cell(*cell), joins=(joins[0], joins[1]))


def _location(
    table: dict[str, Any], i: int, path: Path, region_of: dict[GridCell, str], region_ids: list[str]
) -> Location:
    """``locations[i]``: an item spot on a cell of its region."""
    table = check_keys(table, LOCATION_KEYS, path, entry_of(table, "locations", i))
    lid = table_id(table, path, f"locations[{i}]")
    entry = f"locations[{i}] '{lid}'"
    region = _str(table, "region", path, entry)
    if region not in region_ids:
        raise ScenarioError(path, entry, f"unknown room '{region}'")
    cell = parse_cell(table.get("cell"), path, entry)
    if region_of.get(cell) != region:
        where = f"room '{region_of[cell]}'" if cell in region_of else "a wall"
        raise ScenarioError(path, entry, f"item spot {cell} is in {where}, not in room '{region}'")
    capacity = table.get("capacity")
    if capacity is not None and (not isinstance(capacity, int) or isinstance(capacity, bool) or capacity < 1):
        raise ScenarioError(path, entry, f"capacity must be a positive integer, got {capacity!r}")
    return Location(
        id=lid,
        region=region,
        cell=Cell(*cell),
        play=bool(table.get("play", False)),
        use=bool(table.get("use", False)),
        capacity=capacity,
    )


def _visibility(
    data: dict[str, Any],
    path: Path,
    region_of: dict[GridCell, str],
    doors: list[Door],
    locations: list[Location],
) -> dict[GridCell, tuple[str, ...]]:
    """The spots seen from every walkable cell: a region cell sees the spots of the regions its
    visibility group names (its own when none does), a door cell those of both its regions."""
    region_ids = set(region_of.values())
    sees_regions: dict[str, set[str]] = {}
    for i, table in enumerate(tables(data, "visibility", path)):
        check_keys(table, VISIBILITY_KEYS, path, f"visibility[{i}]")
        for key in ("from", "sees"):
            for rid in table.get(key, []):
                if rid not in region_ids:
                    raise ScenarioError(path, f"visibility[{i}]", f"unknown room '{rid}' in '{key}'")
        for rid in table.get("from", []):
            sees_regions.setdefault(rid, set()).update(table.get("sees", []))
    spots_in: dict[str, list[str]] = {}
    for loc in locations:
        spots_in.setdefault(loc.region, []).append(loc.id)
    order = {loc.id: i for i, loc in enumerate(locations)}

    def spots(regions_seen: set[str]) -> tuple[str, ...]:
        return tuple(sorted((s for r in regions_seen for s in spots_in.get(r, [])), key=order.__getitem__))

    sees = {cell: spots(sees_regions.get(rid, {rid})) for cell, rid in region_of.items()}
    for door in doors:
        sees[(door.cell.col, door.cell.row)] = spots(set(door.joins))
    return sees


def _homes(data: dict[str, Any], path: Path, walkable: Collection[GridCell]) -> dict[str, GridCell]:
    """The agents' home cells (``[homes]``: agent id = cell, any ids), each walkable."""
    table = data.get("homes", {})
    if not isinstance(table, dict):
        raise ScenarioError(path, "homes", f"expected a table of agent = [col, row], got {table!r}")
    homes: dict[str, GridCell] = {}
    for agent, value in table.items():
        cell = parse_cell(value, path, f"homes.{agent}")
        if cell not in walkable:
            raise ScenarioError(path, f"homes.{agent}", f"home cell {cell} is not walkable")
        homes[agent] = cell
    return homes


def _check_reachable(game_map: GameMap) -> None:
    """The map's scene must pass :func:`protocol.scene_problems` (every room reachable...)."""
    problems = scene_problems(game_map.scene((), ()))
    for problem in problems:
        if problem.startswith("unreachable"):
            raise ScenarioError(game_map.path, "doors", f"{problem} (unreachable room)")
    if problems:
        raise ScenarioError(game_map.path, "", "; ".join(problems))


def load_map(name_or_path: str) -> GameMap:
    """Load and check a map, section by section.

    Raises:
        ScenarioError: naming the file, the entry and the problem (an unknown room, a door
            not between two rooms, an item spot in a wall, an unreachable room...).
    """
    path = map_path(name_or_path)
    data = check_keys(read_toml(path), MAP_KEYS, path, "")
    name = _str(data, "name", path, "")
    cell_size, columns, rows = _grid(data, path)
    regions, region_of = _regions(data, path, (columns, rows))
    region_ids = [r.id for r in regions]
    doors = [_door(t, i, path, region_of, region_ids) for i, t in enumerate(tables(data, "doors", path))]
    locations = [
        _location(t, i, path, region_of, region_ids)
        for i, t in enumerate(tables(data, "locations", path, MAX_LOCATIONS))
    ]
    sees = _visibility(data, path, region_of, doors, locations)
    game_map = GameMap(
        name=name,
        path=path,
        cell_size=cell_size,
        columns=columns,
        rows=rows,
        regions=tuple(regions),
        doors=tuple(doors),
        locations=tuple(locations),
        sees=sees,
        homes=_homes(data, path, sees),
    )
    _check_reachable(game_map)
    return game_map


def agent_spec(agent_id: str, kind: AgentKind, home: GridCell, name: str, acts: bool) -> AgentSpec:
    """The protocol description of an agent."""
    radius = 0.3 if kind is AgentKind.ROBOT else 0.25
    return AgentSpec(id=agent_id, kind=kind, home=Cell(*home), name=name, radius=radius, acts=acts)
