"""A scenario as one JSON document, for engines that cannot read TOML (the C# engine).

``python -m sim2d export --scenario NAME [--out FILE]`` (``toyroom export-scenario NAME``)
checks the scenario as sim2d loads it, then writes::

    {"format": "toyroom-scenario/1", "name", "description", "robot": "act" | "observe",
     "tick_seconds", "max_ticks", "settle_ticks",
     "scene": the protocol scene (regions with their cells, doors, locations, visibility),
     "items": [{"id", "at", "absent"}],
     "agents": [{"id", "kind", "name", "home": {"col", "row"}, "wants", "answers", "script"}]}

A script is the scenario file's own list of steps (``{"do": "enter", "region": "S1",
"label": "1"}``...); ``ticks`` count in the scenario's ticks of ``tick_seconds``.
"""

from __future__ import annotations

import tomllib
from typing import Any

import msgspec

from .engine import Engine

FORMAT = "toyroom-scenario/1"


def export(name_or_path: str) -> dict[str, Any]:
    """The JSON-ready export of a bundled scenario name or ``.toml`` path.

    Raises:
        Sim2dError: the scenario or its map is broken (the message names the entry).
    """
    engine = Engine(name_or_path, check_policy=False)
    scenario = engine.scenario
    raw = tomllib.loads(scenario.path.read_text(encoding="utf-8"))
    scripts = {table["id"]: list(table.get("script", [])) for table in raw.get("agents", [])}
    return {
        "format": FORMAT,
        "name": scenario.name,
        "description": scenario.description,
        "robot": scenario.robot,
        "tick_seconds": scenario.tick_seconds,
        "max_ticks": scenario.max_ticks,
        "settle_ticks": scenario.settle_ticks,
        "scene": msgspec.to_builtins(engine.scene()),
        "items": [{"id": i.id, "at": i.at, "absent": i.absent} for i in scenario.items],
        "agents": [
            {
                "id": a.id,
                "kind": a.kind.value,
                "name": a.name,
                "home": {"col": a.home[0], "row": a.home[1]},
                "wants": a.wants,
                "answers": a.answers,
                "script": scripts.get(a.id, []),
            }
            for a in scenario.agents
        ],
    }
