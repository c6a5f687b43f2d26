"""Scenarios as data: a map, items and where they start, agents, and for each scripted
person a route of steps (move, take, drop, play, wait), read from ``<name>.toml``.

Script steps (each a TOML inline table with ``do`` and an optional ``label``; a labelled
step publishes a ``waypoint`` event when the person completes it):

- ``{do = "enter", region = "S1"}``: walk the shortest path until inside the region.
- ``{do = "goto", location = "S1"}`` or ``{do = "goto", cell = [c, r]}``: walk onto it.
- ``{do = "take", item = "ball"}``: take the item from the spot the person stands on.
- ``{do = "drop"}``: put the carried item down at the spot the person stands on.
- ``{do = "play", ticks = 20}``: play with the carried item (on a play spot); without
  ``ticks`` or ``until``, play on until something happens.
- ``{do = "wait", ticks = 40}``, ``{do = "wait", until = "A2:swapped"}`` (until agent A2
  completed its step labelled ``swapped``), or ``{do = "wait"}`` (for good).

A labelled play or take completes when it happens; a move completes on arrival.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any, Literal

from protocol import AgentKind, ItemShape

from .errors import ScenarioError
from .maps import SCENARIO_DIR, GameMap, GridCell, load_map, parse_cell, read_toml

RobotMode = Literal["act", "observe"]


@dataclass(frozen=True)
class Signal:
    """Agent ``agent`` completed its step labelled ``label``."""

    agent: str
    label: str


@dataclass(frozen=True)
class Enter:
    region: str
    label: str | None = None


@dataclass(frozen=True)
class Goto:
    cell: GridCell
    location: str | None = None
    label: str | None = None


@dataclass(frozen=True)
class Take:
    item: str
    label: str | None = None


@dataclass(frozen=True)
class Drop:
    label: str | None = None


@dataclass(frozen=True)
class Play:
    ticks: int | None = None
    until: Signal | None = None
    label: str | None = None


@dataclass(frozen=True)
class Wait:
    ticks: int | None = None
    until: Signal | None = None
    label: str | None = None


Step = Enter | Goto | Take | Drop | Play | Wait


@dataclass(frozen=True)
class ItemSetup:
    """An item and where it starts: ``at`` is a location id or the id of the agent holding it."""

    id: str
    shape: ItemShape
    at: str
    name: str = ""


@dataclass(frozen=True)
class AgentSetup:
    """An agent, its start (home) cell and, for a scripted person, its route.

    ``wants`` is the item the person is after (how it reacts to being told where it is);
    ``answers`` is its answer to a robot's request to hand over what it holds.
    """

    id: str
    kind: AgentKind
    home: GridCell
    name: str = ""
    wants: str | None = None
    answers: bool = False
    script: tuple[Step, ...] = ()
    autonomous: bool = False
    """A simulated person with a true mind and a policy of their own (no script)."""
    prefers: str | None = None
    """An autonomous person's first preference (an item or ``out``); ``None``: drawn from the seed."""


@dataclass(frozen=True)
class Autonomy:
    """How autonomous people behave. Probabilities per tick; durations in ticks (min, max)."""

    switch: float = 0.002
    """Chance per tick that the preference changes."""
    mischief: float = 0.05
    """Chance, when deciding with empty hands, of moving an item that is not one's wish."""
    put_away: float = 0.5
    """Chance of putting an item away (and wanting something else) after playing with it."""
    play_ticks: tuple[int, int] = (60, 200)
    wait_ticks: tuple[int, int] = (20, 60)


@dataclass(frozen=True)
class Scenario:
    """A checked scenario. Times in ticks of ``tick_seconds`` seconds."""

    name: str
    path: Path
    map: GameMap
    description: str
    robot: RobotMode
    observed: str | None
    tick_seconds: float
    max_ticks: int
    settle_ticks: int
    items: tuple[ItemSetup, ...]
    agents: tuple[AgentSetup, ...]
    autonomy: Autonomy = Autonomy()

    @property
    def autonomous(self) -> tuple[AgentSetup, ...]:
        return tuple(a for a in self.agents if a.autonomous)

    @property
    def robots(self) -> tuple[AgentSetup, ...]:
        return tuple(a for a in self.agents if a.kind is AgentKind.ROBOT)

    @property
    def people(self) -> tuple[AgentSetup, ...]:
        return tuple(a for a in self.agents if a.kind is AgentKind.PERSON)


def scenario_names() -> list[str]:
    """The bundled scenarios' names."""
    return sorted(p.stem for p in SCENARIO_DIR.glob("*.toml") if not p.name.endswith(".map.toml"))


def scenario_path(name_or_path: str) -> Path:
    """A bundled scenario's file for a name, or the path itself."""
    candidate = Path(name_or_path)
    if candidate.suffix == ".toml":
        return candidate
    return SCENARIO_DIR / f"{name_or_path}.toml"


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


def _step(table: Any, game_map: GameMap, path: Path, entry: str) -> Step:
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
    return Wait(ticks, until, label)


def load_scenario(name_or_path: str) -> Scenario:
    """Load and check a scenario and its map.

    Raises:
        ScenarioError: naming the file, the entry and the problem.
    """
    path = scenario_path(name_or_path)
    data = read_toml(path)
    name = data.get("name")
    if not isinstance(name, str) or not name:
        raise ScenarioError(path, "name", "expected a non-empty string")
    map_name = data.get("map")
    if not isinstance(map_name, str):
        raise ScenarioError(path, "map", f"expected a map name, got {map_name!r}")
    if map_name.endswith(".toml") and not Path(map_name).is_absolute():
        map_name = str(path.parent / map_name)
    game_map = load_map(map_name)
    robot = data.get("robot", "observe")
    if robot not in ("act", "observe"):
        raise ScenarioError(path, "robot", f"expected 'act' or 'observe', got {robot!r}")

    agents: list[AgentSetup] = []
    raw_agents = data.get("agents", [])
    for i, table in enumerate(raw_agents):
        entry = f"agents[{i}]"
        aid = table.get("id")
        if not isinstance(aid, str) or not aid:
            raise ScenarioError(path, entry, "expected a non-empty string 'id'")
        entry = f"agents[{i}] '{aid}'"
        try:
            kind = AgentKind(table.get("kind", "person"))
        except ValueError:
            raise ScenarioError(
                path, entry, f"expected kind 'person' or 'robot', got {table.get('kind')!r}"
            ) from None
        if "home" in table:
            home = parse_cell(table["home"], path, f"{entry}.home")
            if home not in game_map.walkable:
                raise ScenarioError(path, f"{entry}.home", f"home cell {home} is not walkable")
        elif aid in game_map.homes:
            home = game_map.homes[aid]
        else:
            raise ScenarioError(
                path, entry, f"no home cell: give 'home' or add it to map '{game_map.name}' homes"
            )
        script = tuple(
            _step(step, game_map, path, f"{entry}.script[{j}]")
            for j, step in enumerate(table.get("script", []))
        )
        if kind is AgentKind.ROBOT and script:
            raise ScenarioError(path, entry, "a robot has no script: the brain drives it")
        autonomous = bool(table.get("autonomous", False))
        if autonomous and (script or kind is AgentKind.ROBOT):
            raise ScenarioError(path, entry, "an autonomous person has no script (and is not a robot)")
        answers = table.get("answers", "no")
        if answers not in ("yes", "no"):
            raise ScenarioError(path, entry, f"expected answers = 'yes' or 'no', got {answers!r}")
        agents.append(
            AgentSetup(
                id=aid,
                kind=kind,
                home=home,
                name=str(table.get("name", "")),
                wants=table.get("wants"),
                answers=answers == "yes",
                script=script,
                autonomous=autonomous,
                prefers=table.get("prefers"),
            )
        )
    agent_ids = [a.id for a in agents]
    if len(set(agent_ids)) != len(agent_ids):
        raise ScenarioError(path, "agents", f"duplicate agent ids in {agent_ids}")
    if sum(a.kind is AgentKind.ROBOT for a in agents) > 1:
        raise ScenarioError(path, "agents", "at most one robot per scenario")

    items: list[ItemSetup] = []
    holders: dict[str, str] = {}
    location_ids = {loc.id for loc in game_map.locations}
    for i, table in enumerate(data.get("items", [])):
        iid = table.get("id")
        if not isinstance(iid, str) or not iid:
            raise ScenarioError(path, f"items[{i}]", "expected a non-empty string 'id'")
        entry = f"items[{i}] '{iid}'"
        try:
            shape = ItemShape(table.get("shape", "block"))
        except ValueError:
            known = ", ".join(s.value for s in ItemShape)
            raise ScenarioError(
                path, entry, f"unknown shape {table.get('shape')!r}; known: {known}"
            ) from None
        at = table.get("at")
        if at in agent_ids:
            if at in holders:
                raise ScenarioError(path, entry, f"agent '{at}' already holds '{holders[at]}'")
            holders[at] = iid
        elif at not in location_ids:
            raise ScenarioError(
                path,
                entry,
                f"'at' must be a location ({', '.join(sorted(location_ids))}) or an agent, got {at!r}",
            )
        items.append(ItemSetup(id=iid, shape=shape, at=at, name=str(table.get("name", ""))))
    item_ids = {item.id for item in items}
    if len(item_ids) != len(items):
        raise ScenarioError(path, "items", "duplicate item ids")
    if item_ids & set(agent_ids):
        raise ScenarioError(
            path, "items", f"ids used by both an item and an agent: {sorted(item_ids & set(agent_ids))}"
        )

    labels = {(a.id, s.label) for a in agents for s in a.script if s.label}
    for i, agent in enumerate(agents):
        if agent.wants is not None and agent.wants not in item_ids:
            raise ScenarioError(path, f"agents[{i}] '{agent.id}'", f"wants unknown item {agent.wants!r}")
        if agent.prefers is not None and agent.prefers not in item_ids | {"out"}:
            raise ScenarioError(path, f"agents[{i}] '{agent.id}'", f"prefers unknown item {agent.prefers!r}")
        for j, step in enumerate(agent.script):
            entry = f"agents[{i}] '{agent.id}'.script[{j}]"
            if isinstance(step, Take) and step.item not in item_ids:
                raise ScenarioError(
                    path, entry, f"unknown item {step.item!r}; items: {', '.join(sorted(item_ids))}"
                )
            until = getattr(step, "until", None)
            if until is not None and (until.agent, until.label) not in labels:
                raise ScenarioError(
                    path, entry, f"no agent '{until.agent}' step labelled '{until.label}' to wait for"
                )

    observed = data.get("observed")
    if observed is not None and observed not in agent_ids:
        raise ScenarioError(path, "observed", f"unknown agent {observed!r}")
    try:
        tick_seconds = float(data.get("tick_seconds", 0.1))
        max_ticks = int(data.get("max_ticks", 3000))
        settle_ticks = int(data.get("settle_ticks", 1))
    except (TypeError, ValueError) as err:
        raise ScenarioError(
            path, "", f"expected numbers tick_seconds, max_ticks, settle_ticks ({err})"
        ) from None
    if tick_seconds <= 0 or max_ticks < 1 or settle_ticks < 1:
        raise ScenarioError(path, "", "tick_seconds must be > 0, max_ticks and settle_ticks >= 1")
    table = data.get("autonomy", {})
    try:
        autonomy = Autonomy(
            switch=float(table.get("switch", Autonomy.switch)),
            mischief=float(table.get("mischief", Autonomy.mischief)),
            put_away=float(table.get("put_away", Autonomy.put_away)),
            play_ticks=tuple(table.get("play_ticks", Autonomy.play_ticks)),  # type: ignore[arg-type]
            wait_ticks=tuple(table.get("wait_ticks", Autonomy.wait_ticks)),  # type: ignore[arg-type]
        )
    except (TypeError, ValueError) as err:
        raise ScenarioError(path, "autonomy", f"expected numbers and [min, max] tick pairs ({err})") from None
    return Scenario(
        name=name,
        path=path,
        map=game_map,
        description=str(data.get("description", "")),
        robot=robot,
        observed=observed,
        tick_seconds=tick_seconds,
        max_ticks=max_ticks,
        settle_ticks=settle_ticks,
        items=tuple(items),
        agents=tuple(agents),
        autonomy=autonomy,
    )
