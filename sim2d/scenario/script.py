"""A scripted person's route: the steps of ``script = [...]`` in a scenario file.

Each step is a TOML inline table with ``do`` and an optional ``label``; a labelled step
publishes a ``waypoint`` event when the person completes it:

- ``{do = "enter", region = "S1"}``: walk the shortest path until inside the region.
- ``{do = "goto", location = "S1"}`` or ``{do = "goto", cell = [c, r]}``: walk onto it.
- ``{do = "take", item = "ball"}``: take the item from the spot the person stands on.
- ``{do = "drop"}``: put the carried item down at the spot the person stands on.
- ``{do = "play", ticks = 20}``: play with the carried item (on a play spot); without
  ``ticks`` or ``until``, play on until something happens.
- ``{do = "use", item = "cake", ticks = 20}``: use an item resting at the ``use`` location
  the person stands on, in place (eating at a stall), for ``ticks`` (or ``until``).
- ``{do = "wait", ticks = 40}``, ``{do = "wait", until = "A2:swapped"}`` (until agent A2
  completed its step labelled ``swapped``), or ``{do = "wait"}`` (for good).

A labelled play or take completes when it happens; a move completes on arrival.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from protocol import GridCell

from ..errors import ScenarioError
from .maps import GameMap, parse_cell


@dataclass(frozen=True)
class Signal:
    """Agent ``agent`` completed its step labelled ``label``."""

    agent: str
    label: str


@dataclass(frozen=True)
class Enter:
    """``{do = "enter", region = ...}``: walk the shortest path until inside the region."""

    region: str
    label: str | None = None


@dataclass(frozen=True)
class Goto:
    """``{do = "goto", ...}``: walk onto a cell (of a location, when named)."""

    cell: GridCell
    location: str | None = None
    label: str | None = None


@dataclass(frozen=True)
class Take:
    """``{do = "take", item = ...}``: take the item from the spot the person stands on."""

    item: str
    label: str | None = None


@dataclass(frozen=True)
class Drop:
    """``{do = "drop"}``: put the carried item down at the spot the person stands on."""

    label: str | None = None


@dataclass(frozen=True)
class Play:
    """``{do = "play"}``: play with the carried item for ``ticks``, ``until`` a signal, or on."""

    ticks: int | None = None
    until: Signal | None = None
    label: str | None = None


@dataclass(frozen=True)
class Use:
    """``{do = "use", item = ...}``: use an item resting at the person's ``use`` location, in place."""

    item: str
    ticks: int | None = None
    until: Signal | None = None
    label: str | None = None


@dataclass(frozen=True)
class Wait:
    """``{do = "wait"}``: wait for ``ticks``, ``until`` a signal, or for good."""

    ticks: int | None = None
    until: Signal | None = None
    label: str | None = None


Step = Enter | Goto | Take | Drop | Play | Use | Wait


def _signal(value: Any, path: Path, entry: str) -> Signal:
    if not isinstance(value, str) or value.count(":") != 1:
        raise ScenarioError(path, entry, f'expected until = "AGENT:LABEL", got {value!r}')
    agent, label = value.split(":")
    return Signal(agent, label)


def _positive(value: Any, path: Path, entry: str, key: str) -> int | None:
    if value is None:
        return None
    if not isinstance(value, int) or isinstance(value, bool) or value < 1:
        raise ScenarioError(path, entry, f"expected {key} to be a positive integer, got {value!r}")
    return value


def parse_step(table: Any, game_map: GameMap, path: Path, entry: str) -> Step:
    """One step of a script, read from its inline table (``entry`` of ``path``, for the error)."""
    if not isinstance(table, dict):
        raise ScenarioError(path, entry, f"expected a table {{do = ...}}, got {table!r}")
    do = table.get("do")
    label = table.get("label")
    if label is not None and not isinstance(label, str):
        raise ScenarioError(path, entry, f"expected a string label, got {label!r}")
    allowed = {
        "enter": {"region"},
        "goto": {"location", "cell"},
        "take": {"item"},
        "drop": set(),
        "play": {"ticks", "until"},
        "use": {"item", "ticks", "until"},
        "wait": {"ticks", "until"},
    }
    if do not in allowed:
        raise ScenarioError(path, entry, f"unknown step do = {do!r}; known: {', '.join(allowed)}")
    extra = set(table) - allowed[do] - {"do", "label"}
    if extra:
        raise ScenarioError(path, entry, f"'{do}' takes no {', '.join(sorted(extra))}")
    region_ids = {r.id for r in game_map.regions}
    if do == "enter":
        region = table.get("region")
        if region not in region_ids:
            raise ScenarioError(
                path, entry, f"unknown room {region!r}; rooms: {', '.join(sorted(region_ids))}"
            )
        return Enter(region, label)
    if do == "goto":
        if "location" in table:
            try:
                loc = game_map.location(table["location"])
            except KeyError:
                known = ", ".join(loc.id for loc in game_map.locations)
                raise ScenarioError(
                    path, entry, f"unknown location {table['location']!r}; locations: {known}"
                ) from None
            return Goto((loc.cell.col, loc.cell.row), loc.id, label)
        if "cell" not in table:
            raise ScenarioError(path, entry, "goto needs a location or a cell")
        cell = parse_cell(table["cell"], path, entry)
        if cell not in game_map.walkable:
            raise ScenarioError(path, entry, f"cell {cell} is not walkable")
        return Goto(cell, None, label)
    if do == "take":
        return Take(str(table.get("item", "")), label)
    if do == "drop":
        return Drop(label)
    ticks = _positive(table.get("ticks"), path, entry, "ticks")
    until = _signal(table["until"], path, entry) if "until" in table else None
    if do == "play":
        return Play(ticks, until, label)
    if do == "use":
        return Use(str(table.get("item", "")), ticks, until, label)
    return Wait(ticks, until, label)
