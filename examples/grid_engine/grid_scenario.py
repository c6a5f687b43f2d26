"""Reading the shared scenario files (``sim2d/scenarios/*.toml``) for the grid engine.

Written from the file format alone: a map is rooms as cell rectangles, doors, item spots,
visibility groups and home cells; a scenario is a map, items, agents and scripts.
"""

from __future__ import annotations

import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

Cell = tuple[int, int]


@dataclass
class Map:
    name: str
    columns: int
    rows: int
    cell_size: float
    regions: list[dict[str, Any]]  # {"id", "kind", "name", "cells": [Cell]}
    doors: list[dict[str, Any]]  # {"id", "cell": Cell, "joins": [a, b]}
    locations: list[dict[str, Any]]  # {"id", "region", "cell": Cell, "play", "use": bool, "capacity"}
    sees: dict[Cell, list[str]]
    homes: dict[str, Cell]
    region_of: dict[Cell, str] = field(default_factory=dict)

    @property
    def walkable(self) -> set[Cell]:
        return set(self.region_of) | {d["cell"] for d in self.doors}


@dataclass
class Scenario:
    name: str
    map: Map
    robot_acts: bool
    tick_seconds: float  # of the scenario's own ticks (script ``ticks`` count in these)
    max_ticks: int
    settle_ticks: int
    items: list[dict[str, Any]]  # {"id", "shape", "name", "at", "absent"}
    agents: list[
        dict[str, Any]
    ]  # {"id", "kind", "name", "home": Cell, "wants", "answers": bool, "script": [...]}


def _cell(value: list[int]) -> Cell:
    return (int(value[0]), int(value[1]))


def read_map(path: Path) -> Map:
    data = tomllib.loads(path.read_text(encoding="utf-8"))
    regions, region_of = [], {}
    for table in data["regions"]:
        cells = [
            (c, r)
            for col, row, width, height in table["rects"]
            for c in range(col, col + width)
            for r in range(row, row + height)
        ]
        for cell in cells:
            region_of[cell] = table["id"]
        regions.append(
            {
                "id": table["id"],
                "kind": table.get("kind", "room"),
                "name": table.get("name", ""),
                "cells": cells,
            }
        )
    doors = [
        {"id": d["id"], "cell": _cell(d["cell"]), "joins": list(d["joins"])} for d in data.get("doors", [])
    ]
    locations = [
        {
            "id": loc["id"],
            "region": loc["region"],
            "cell": _cell(loc["cell"]),
            "play": bool(loc.get("play", False)),
            "use": bool(loc.get("use", False)),
            "capacity": loc.get("capacity"),
        }
        for loc in data.get("locations", [])
    ]
    groups: dict[str, set[str]] = {}
    for group in data.get("visibility", []):
        for region in group["from"]:
            groups.setdefault(region, set()).update(group["sees"])
    order = [loc["id"] for loc in locations]

    def spots(regions_seen: set[str]) -> list[str]:
        return [loc["id"] for loc in locations if loc["region"] in regions_seen]

    sees = {cell: spots(groups.get(region, {region})) for cell, region in region_of.items()}
    for door in doors:
        sees[door["cell"]] = spots(set(door["joins"]))
    for cell in sees:
        sees[cell].sort(key=order.index)
    homes = {agent: _cell(cell) for agent, cell in data.get("homes", {}).items()}
    game_map = Map(
        data["name"],
        int(data["columns"]),
        int(data["rows"]),
        float(data.get("cell_size", 1.0)),
        regions,
        doors,
        locations,
        sees,
        homes,
    )
    game_map.region_of = region_of
    return game_map


def read_scenario(path: Path) -> Scenario:
    data = tomllib.loads(path.read_text(encoding="utf-8"))
    map_name = data["map"]
    # a .toml path is relative to the scenario's folder, a name is <name>.map.toml beside it
    map_path = path.parent / (map_name if map_name.endswith(".toml") else f"{map_name}.map.toml")
    game_map = read_map(map_path)
    agents = []
    for table in data.get("agents", []):
        home = _cell(table["home"]) if "home" in table else game_map.homes[table["id"]]
        agents.append(
            {
                "id": table["id"],
                "kind": table.get("kind", "person"),
                "name": table.get("name", ""),
                "home": home,
                "wants": table.get("wants"),
                "answers": table.get("answers", "no") == "yes",
                "script": list(table.get("script", [])),
            }
        )
    return Scenario(
        name=data["name"],
        map=game_map,
        robot_acts=data.get("robot", "observe") == "act",
        tick_seconds=float(data.get("tick_seconds", 0.1)),
        max_ticks=int(data.get("max_ticks", 3000)),
        settle_ticks=int(data.get("settle_ticks", 1)),
        items=[
            {
                "id": i["id"],
                "shape": i.get("shape", "block"),
                "name": i.get("name", ""),
                "at": i.get("at"),
                "absent": bool(i.get("absent", False)),
            }
            for i in data.get("items", [])
        ],
        agents=agents,
    )


def scaled(ticks: int | None, scenario_tick: float, engine_tick: float) -> int | None:
    """A duration in the scenario's ticks, in this engine's (longer) ticks."""
    return None if ticks is None else max(1, math.ceil(ticks * scenario_tick / engine_tick))
