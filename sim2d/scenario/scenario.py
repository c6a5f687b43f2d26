"""Scenarios as data: a map, items and where they start, agents, and for each scripted
person a route of steps (:mod:`sim2d.scenario.script`), read from ``<name>.toml`` and checked section
by section. Every table is strict (:mod:`sim2d.scenario.tables`): an unknown key is an error naming
it. ``map = "NAME"`` plays ``NAME.map.toml`` beside the scenario when there is one, else the
bundled map of that name."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import msgspec

from protocol import MAX_AGENTS, MAX_ITEMS, AgentKind, GridCell, Household, ItemShape, RobotMode, Study
from protocol.message import id_problem

from ..errors import ScenarioError
from .autonomy import Autonomy, parse_autonomy
from .jobs import JOB_KEYS, Jobs, job_items, parse_jobs
from .maps import SCENARIO_DIR, GameMap, load_map, parse_cell, read_toml
from .numbers import integer, real
from .script import Step, Take, parse_step
from .tables import AGENT_KEYS, ITEM_KEYS, SCENARIO_KEYS, check_keys, entry_of, table_id, tables

MAX_TICK_SECONDS = 3600.0
"""The longest tick (s) a scenario may have: a finite time, its multiples too."""
MIN_TICK_SECONDS = 0.01
"""The shortest tick (s) a scenario may have. A person walks a cell in 0.67 s (1.5 m/s): at
10 ms that is 67 ticks, each a lock-step round and a brain update, against 7 at the bundled
0.1 s; a finer tick adds ticks and nothing else (at ``1e-9`` s a walk to the next cell would
take 670 million ticks, and a free-running engine could not keep to its clock)."""
TICK_FLOOR_WHY = "a walk to the next cell takes 0.67 s; a finer tick only adds ticks"
"""Why :data:`MIN_TICK_SECONDS`, in the loader's error."""


@dataclass(frozen=True)
class ItemSetup:
    """An item and where it starts: ``at`` is a location id or the id of the agent holding it
    (empty for an ``absent`` item: people may want it, it is not in the scene)."""

    id: str
    shape: ItemShape
    at: str
    name: str = ""
    absent: bool = False


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
    jobs: Jobs = Jobs()
    """An autonomous person's first jobs in a task episode (:mod:`sim2d.scenario.jobs`)."""


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
    household: Household | None = None
    """The household and day the episode is (``[household]``: ``id``, ``day`` from 1), if any."""
    study: Study | None = None
    """What a participant playing this scenario is told and asked (``[study]``), if any."""

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


def _map_of(data: dict[str, Any], path: Path) -> GameMap:
    """The scenario's map: a ``.toml`` path (relative to the scenario), or a name: the file
    ``<name>.map.toml`` beside the scenario when there is one (so a copied scenario plays
    its copied map), else the bundled map of that name."""
    map_name = data.get("map")
    if not isinstance(map_name, str) or not map_name:
        raise ScenarioError(path, "map", f"expected a map name, got {map_name!r}")
    if map_name.endswith(".toml"):
        return load_map(map_name if Path(map_name).is_absolute() else str(path.parent / map_name))
    beside = path.parent / f"{map_name}.map.toml"
    return load_map(str(beside) if beside.is_file() else map_name)


def _home(table: dict[str, Any], aid: str, game_map: GameMap, path: Path, entry: str) -> GridCell:
    """An agent's home: its ``home`` cell, or the map's home for it."""
    if "home" in table:
        home = parse_cell(table["home"], path, f"{entry}.home")
        if home not in game_map.walkable:
            raise ScenarioError(path, f"{entry}.home", f"home cell {home} is not walkable")
        return home
    if aid in game_map.homes:
        return game_map.homes[aid]
    raise ScenarioError(path, entry, f"no home cell: give 'home' or add it to map '{game_map.name}' homes")


def _entry_id(table: dict[str, Any], section: str, i: int, path: Path) -> tuple[str, str]:
    """The ``id`` of ``section[i]`` (a protocol id: :func:`.tables.table_id`) and the entry
    name errors give it."""
    value = table_id(table, path, f"{section}[{i}]")
    return value, f"{section}[{i}] '{value}'"


def _agent(table: dict[str, Any], i: int, game_map: GameMap, path: Path) -> AgentSetup:
    """``agents[i]``: a person (scripted or autonomous) or the robot."""
    table = check_keys(table, AGENT_KEYS, path, entry_of(table, "agents", i))
    aid, entry = _entry_id(table, "agents", i, path)
    try:
        kind = AgentKind(table.get("kind", "person"))
    except ValueError:
        raise ScenarioError(
            path, entry, f"expected kind 'person' or 'robot', got {table.get('kind')!r}"
        ) from None
    home = _home(table, aid, game_map, path, entry)
    script = tuple(
        parse_step(step, game_map, path, f"{entry}.script[{j}]")
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
    jobs = parse_jobs(table, game_map, path, entry)
    if jobs.any and not autonomous:
        raise ScenarioError(path, entry, f"{JOB_KEYS} are for autonomous people")
    return AgentSetup(
        id=aid,
        kind=kind,
        home=home,
        name=str(table.get("name", "")),
        wants=table.get("wants"),
        answers=answers == "yes",
        script=script,
        autonomous=autonomous,
        prefers=table.get("prefers"),
        jobs=jobs,
    )


def _agents(data: dict[str, Any], game_map: GameMap, path: Path) -> list[AgentSetup]:
    """Every agent, with distinct ids and at most one robot."""
    listed = tables(data, "agents", path, MAX_AGENTS)
    agents = [_agent(table, i, game_map, path) for i, table in enumerate(listed)]
    agent_ids = [a.id for a in agents]
    if len(set(agent_ids)) != len(agent_ids):
        raise ScenarioError(path, "agents", f"duplicate agent ids in {agent_ids}")
    if sum(a.kind is AgentKind.ROBOT for a in agents) > 1:
        raise ScenarioError(path, "agents", "at most one robot per scenario")
    return agents


def _item(
    table: dict[str, Any],
    i: int,
    path: Path,
    location_ids: set[str],
    agent_ids: list[str],
    holders: dict[str, str],
) -> ItemSetup:
    """``items[i]``: at a location, or held by an agent (one item per agent, noted in ``holders``)."""
    table = check_keys(table, ITEM_KEYS, path, entry_of(table, "items", i))
    iid, entry = _entry_id(table, "items", i, path)
    try:
        shape = ItemShape(table.get("shape", "block"))
    except ValueError:
        known = ", ".join(s.value for s in ItemShape)
        raise ScenarioError(path, entry, f"unknown shape {table.get('shape')!r}; known: {known}") from None
    at = table.get("at")
    absent = table.get("absent", False)
    if not isinstance(absent, bool):
        raise ScenarioError(path, entry, f"absent must be true or false, got {absent!r}")
    if absent:
        if at is not None:
            raise ScenarioError(path, entry, f"an absent item has no 'at', got {at!r}")
        return ItemSetup(id=iid, shape=shape, at="", name=str(table.get("name", "")), absent=True)
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
    return ItemSetup(id=iid, shape=shape, at=at, name=str(table.get("name", "")))


def _items(data: dict[str, Any], game_map: GameMap, path: Path, agents: list[AgentSetup]) -> list[ItemSetup]:
    """Every item, with ids distinct from each other and from the agents'."""
    agent_ids = [a.id for a in agents]
    location_ids = {loc.id for loc in game_map.locations}
    holders: dict[str, str] = {}
    items = [
        _item(table, i, path, location_ids, agent_ids, holders)
        for i, table in enumerate(tables(data, "items", path, MAX_ITEMS))
    ]
    item_ids = {item.id for item in items}
    if len(item_ids) != len(items):
        raise ScenarioError(path, "items", "duplicate item ids")
    if item_ids & set(agent_ids):
        raise ScenarioError(
            path, "items", f"ids used by both an item and an agent: {sorted(item_ids & set(agent_ids))}"
        )
    return items


def _check_references(agents: list[AgentSetup], item_ids: set[str], path: Path) -> None:
    """What people want, prefer, take and wait for must exist."""
    labels = {(a.id, s.label) for a in agents for s in a.script if s.label}
    for i, agent in enumerate(agents):
        if agent.wants is not None and agent.wants not in item_ids:
            raise ScenarioError(path, f"agents[{i}] '{agent.id}'", f"wants unknown item {agent.wants!r}")
        if agent.prefers is not None and agent.prefers not in item_ids | {"out"}:
            raise ScenarioError(path, f"agents[{i}] '{agent.id}'", f"prefers unknown item {agent.prefers!r}")
        for key, item in job_items(agent.jobs):
            if item not in item_ids:
                raise ScenarioError(path, f"agents[{i}] '{agent.id}'", f"{key}: unknown item {item!r}")
        listener = agent.jobs.tells[0] if agent.jobs.tells else None
        if listener is not None and listener not in {a.id for a in agents if a.autonomous} - {agent.id}:
            problem = f"tell: {listener!r} is no other autonomous person"
            raise ScenarioError(path, f"agents[{i}] '{agent.id}'", problem)
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


def _timing(data: dict[str, Any], path: Path) -> tuple[float, int, int]:
    """``tick_seconds`` (s, finite, from :data:`MIN_TICK_SECONDS` to :data:`MAX_TICK_SECONDS`),
    ``max_ticks`` and ``settle_ticks`` (integers, at least 1)."""
    seconds = data.get("tick_seconds", 0.1)
    tick_seconds = real(
        seconds, path, "tick_seconds", "tick_seconds", MAX_TICK_SECONDS, MIN_TICK_SECONDS, TICK_FLOOR_WHY
    )
    max_ticks = integer(data.get("max_ticks", 3000), path, "max_ticks", "max_ticks")
    settle_ticks = integer(data.get("settle_ticks", 1), path, "settle_ticks", "settle_ticks")
    return tick_seconds, max_ticks, settle_ticks


def load_scenario(name_or_path: str) -> Scenario:
    """Load and check a scenario and its map, section by section.

    Raises:
        ScenarioError: naming the file, the entry and the problem.
    """
    path = scenario_path(name_or_path)
    data = check_keys(read_toml(path), SCENARIO_KEYS, path, "")
    name = data.get("name")
    if not isinstance(name, str) or not name:
        raise ScenarioError(path, "name", "expected a non-empty string")
    game_map = _map_of(data, path)
    robot = data.get("robot", RobotMode.OBSERVE)
    if robot not in RobotMode.names():
        expected = " or ".join(map(repr, RobotMode.names()))
        raise ScenarioError(path, "robot", f"expected {expected}, got {robot!r}")
    agents = _agents(data, game_map, path)
    items = _items(data, game_map, path, agents)
    _check_references(agents, {item.id for item in items}, path)
    observed = data.get("observed")
    if observed is not None and observed not in {a.id for a in agents}:
        raise ScenarioError(path, "observed", f"unknown agent {observed!r}")
    tick_seconds, max_ticks, settle_ticks = _timing(data, path)
    return Scenario(
        name=name,
        path=path,
        map=game_map,
        description=str(data.get("description", "")),
        robot=RobotMode(robot),
        observed=observed,
        tick_seconds=tick_seconds,
        max_ticks=max_ticks,
        settle_ticks=settle_ticks,
        items=tuple(items),
        agents=tuple(agents),
        autonomy=parse_autonomy(data, path),
        household=_household(data, path),
        study=_study(data, path, game_map, {item.id for item in items}, agents),
    )


def _household(data: dict[str, Any], path: Path) -> Household | None:
    """The ``[household]`` table: ``id`` (a non-empty string), ``day`` (an integer >= 1)."""
    table = data.get("household")
    if table is None:
        return None
    if not isinstance(table, dict):
        raise ScenarioError(path, "household", "expected a table with id and day")
    table = check_keys(table, frozenset({"id", "day"}), path, "household")
    ident = table.get("id")
    if not isinstance(ident, str) or not ident:
        raise ScenarioError(path, "household", f"id must be a non-empty string, got {ident!r}")
    if (problem := id_problem(ident)) is not None:
        raise ScenarioError(path, "household", f"id {problem}")
    return Household(id=ident, day=integer(table.get("day", 1), path, "household", "day"))


def _study(
    data: dict[str, Any], path: Path, game_map: GameMap, items: set[str], agents: list[AgentSetup]
) -> Study | None:
    """The ``[study]`` table (:class:`protocol.Study`): strict keys, a goal of one condition
    naming an item or a region of the scenario (``after``: a label of a person's script), a
    positive time limit."""
    table = data.get("study")
    if table is None:
        return None
    try:
        study = msgspec.convert(table, Study)
    except msgspec.ValidationError as err:
        raise ScenarioError(path, "study", str(err)) from None
    goal = study.reached
    if goal is not None:
        problem = goal.problem()
        if problem is not None:
            raise ScenarioError(path, "study.reached", problem)
        for key, known, what in (
            ("holds", items, "item"),
            ("plays", items, "item"),
            ("enters", {r.id for r in game_map.regions}, "region"),
        ):
            value = getattr(goal, key)
            if value is not None and value not in known:
                known_ = ", ".join(sorted(known))
                raise ScenarioError(path, f"study.reached.{key}", f"no {what} {value!r} (known: {known_})")
        labels = {step.label for agent in agents for step in agent.script if step.label is not None}
        if goal.after is not None and goal.after not in labels:
            raise ScenarioError(path, "study.reached.after", f"no step is labelled {goal.after!r}")
    return study
