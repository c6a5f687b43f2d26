"""Random episodes: scenario (and map) files made from a seed.

- :func:`~.houses.house_map` (re-exported here): a generated house.
- :func:`episode`: a scenario on a map: items at random spots, two autonomous people with
  hidden preferences drawn from the seed, random mischief and patience, an acting robot.

Everything is TOML text in the same format as the bundled files, so any engine that reads
those (sim2d, the grid engine) plays them.
"""

from __future__ import annotations

import tomllib
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from protocol import (
    DEFAULT_EPISODE,
    EpisodeKind,
    EpisodeMap,
    EpisodeSpec,
    GridCell,
    Minds,
    Morning,
    RobotMode,
)
from protocol import MAPS as MAPS

from ..scenario.maps import SCENARIO_DIR, GameMap, load_map
from .households import day_seed, household_lines, night
from .houses import house_map as house_map
from .mornings import by_favourites, check_morning, with_beliefs
from .overrides import parse_overrides, with_autonomy
from .tasks import TASKS, check_kinds, person_lines, task_agents

ITEM_SHAPES = (
    ("ball", "ball"),
    ("skate", "board"),
    ("block", "block"),
    ("marble", "marble"),
    ("car", "block"),
    ("frisbee", "ball"),
    ("kite", "board"),
    ("top", "marble"),
    ("puzzle", "block"),
    ("yoyo", "marble"),
)
"""Item ids and shapes, in the order episodes use them (at most this many items)."""


MINDS = Minds.names()
"""Kinds of simulated minds (:class:`protocol.Minds`): ``simple`` people perceive exactly,
remember, keep to themselves and go where they believe their item most likely is (what the
brain's percept filter assumes); ``rich`` ones get the knobs :func:`rich_autonomy` draws;
``model`` ones perceive as simple ones do and act by the brain's planner
(``planner = "model"``: the engine needs the table ``python -m brain plan`` writes)."""


def rich_autonomy(seed: int) -> list[str]:
    """The ``[autonomy]`` lines of a rich mind, drawn from ``seed`` (apart from every other
    draw of the episode, so a rich episode has the same items, homes and habits as the
    simple one of its seed)."""
    rng = np.random.default_rng([seed, 1])
    return [
        f"forget_per_tick = {rng.uniform(0.0002, 0.001):.5f}",
        f"miss = {rng.uniform(0.1, 0.4):.3f}",
        f"hearsay_per_tick = {rng.uniform(0.01, 0.05):.4f}",
        f'search = "{("likely", "nearest")[int(rng.integers(2))]}"',
        f"wander = {rng.uniform(0.0, 0.15):.3f}",
        f"replan = {rng.uniform(0.0, 0.02):.4f}",
        f"knows = {rng.uniform(0.3, 0.7):.3f}",
        f"stale = {rng.uniform(0.1, 0.3):.3f}",
        f"silent = {rng.uniform(0.2, 0.5):.3f}",  # drawn last: the draws before are as they were
    ]


TICK_SECONDS = 0.1
"""A generated episode's tick (s)."""

KINDS = EpisodeKind.names()
"""Kinds of episodes (:class:`protocol.EpisodeKind`): ``everyday`` (people with random
habits) or ``tasks`` (built around the robot's jobs, :data:`TASKS`, with people who never
change their minds, put nothing away and move nothing but what the task says, so that the job
stays the job)."""


def episode(
    name: str,
    map_ref: str,
    map_path: Path,
    items: int,
    seed: int,
    spec: EpisodeSpec = DEFAULT_EPISODE,
    *,
    people: int = 2,
    morning: Morning | None = None,
) -> str:
    """The TOML text of a random episode on the map at ``map_path``, which the file names as
    ``map_ref`` (a bundled map's name, or a file name beside the episode: no absolute paths,
    so a folder of episodes can be moved or shared), drawn as ``spec`` says (its ``minds``:
    one of :data:`MINDS`; its ``kind``: one of :data:`KINDS`; its ``tasks``: the task kinds a
    ``tasks`` episode is drawn from, empty: all of :data:`~sim2d.generation.tasks.TASKS`; its
    ``autonomy`` is the writers' to apply); ``people``: how many (everyday episodes; people
    past the second get homes of their own draw, so the first two's episode is the same);
    ``morning``: a day of a household after the first
    (:mod:`.households`): items where the morning has them, each person sure of what they
    were sure of at night (rich minds draw no ``knows`` or ``stale`` on top), wanting what
    they wanted most (a task is built around the first person's favourite item)."""
    minds, kind, max_ticks, tasks = spec.minds, spec.kind, spec.max_ticks, spec.tasks or None
    if people < 1 or (kind == EpisodeKind.TASKS and people != 2):
        raise ValueError(f"an episode has at least 1 person (tasks: 2), not {people}")
    if minds not in MINDS:
        raise ValueError(f"minds must be one of {', '.join(MINDS)}, not {minds!r}")
    if kind not in KINDS:
        raise ValueError(f"kind must be one of {', '.join(KINDS)}, not {kind!r}")
    rng = np.random.default_rng(seed)
    game_map = load_map(str(map_path))
    rich = rich_autonomy(seed) if minds == Minds.RICH else []
    if morning is not None and rich:  # the night's beliefs, not a fresh draw
        rich = [line for line in rich if line.split(" =")[0] not in ("knows", "stale")]
        rich += ["knows = 0.0", "stale = 0.0"]
    search = next((line.split('"')[1] for line in rich if line.startswith("search")), "likely")
    spots = [loc.id for loc in game_map.locations]
    cells = sorted(
        c
        for c, r in game_map.region_of.items()
        if r != "O" and c not in {(loc.cell.col, loc.cell.row) for loc in game_map.locations}
    )
    picks = rng.choice(len(cells), size=3, replace=False)
    homes = [cells[int(i)] for i in picks]
    lines = [
        f"# A generated episode (seed {seed}) on map {game_map.name}.",
        f'name = "{name}"',
        f'map = "{map_ref}"',
        f'robot = "{RobotMode.ACT}"',
        f"tick_seconds = {TICK_SECONDS}",
        f"max_ticks = {max_ticks}",
        "",
        "[autonomy]",
        f"switch = {rng.uniform(0.0005, 0.002) * (kind != EpisodeKind.TASKS):.5f}",
        f"mischief = {rng.uniform(0.05, 0.3) * (kind != EpisodeKind.TASKS):.3f}",
        f"put_away = {rng.uniform(0.3, 0.8) * (kind != EpisodeKind.TASKS):.3f}",
        "play_ticks = [60, 200]",
        "wait_ticks = [20, 60]",
        *rich,
        *(['planner = "model"'] if minds == Minds.MODEL else []),
        "",
    ]
    if not 1 <= items <= len(ITEM_SHAPES):
        raise ValueError(f"an episode has 1 to {len(ITEM_SHAPES)} items, not {items}")
    placed: dict[str, str] = {}
    for k in range(items):
        item, shape = ITEM_SHAPES[k]
        placed[item] = spots[int(rng.integers(len(spots)))]
        if morning is not None:
            placed[item] = morning.items.get(item, placed[item])
        lines += ["[[items]]", f'id = "{item}"', f'shape = "{shape}"', f'at = "{placed[item]}"', ""]
    people_of = _task_people if kind == EpisodeKind.TASKS else _everyday_people
    agents = people_of(game_map, placed, homes, cells, seed, search, tasks, people, morning)
    lines += agents if morning is None else with_beliefs(agents, morning.beliefs)
    lines += ["[[agents]]", 'id = "robot"', 'kind = "robot"', f"home = [{homes[2][0]}, {homes[2][1]}]", ""]
    return "\n".join(lines)


def _task_people(
    game_map: GameMap,
    placed: dict[str, str],
    homes: list[GridCell],
    cells: list[GridCell],
    seed: int,
    search: str,
    tasks: Sequence[str] | None,
    people: int,
    morning: Morning | None,
) -> list[str]:
    """The two people of a task episode (the task about the first person's favourite)."""
    kinds = TASKS if tasks is None else check_kinds(tasks)
    favourites = {} if morning is None else morning.favourites
    ordered = by_favourites(placed, favourites)
    return task_agents(game_map, ordered, homes, seed, tick_seconds=TICK_SECONDS, search=search, kinds=kinds)


def _everyday_people(
    game_map: GameMap,
    placed: dict[str, str],
    homes: list[GridCell],
    cells: list[GridCell],
    seed: int,
    search: str,
    tasks: Sequence[str] | None,
    people: int,
    morning: Morning | None,
) -> list[str]:
    """The people of an everyday episode (past the second, homes of their own draw), each
    wanting what the morning says they want most, if anything."""
    favourites = {} if morning is None else morning.favourites
    more = np.random.default_rng([seed, 1]).choice(len(cells), size=max(0, people - 2))
    agents: list[str] = []
    for n, home in enumerate([*homes[: min(people, 2)], *(cells[int(i)] for i in more)]):
        wants = favourites.get(f"A{n + 1}")
        agents += person_lines(f"A{n + 1}", home, *([f'prefers = "{wants}"'] if wants else []))
    return agents


HOUSES = {EpisodeMap.HOUSE_A: (5, 4, 11), EpisodeMap.HOUSE_B: (6, 4, 23)}
"""The generated houses among the maps episodes are drawn on (:data:`protocol.MAPS`,
re-exported here as ``MAPS``): rooms, spots, seed; the others are bundled maps."""

ITEMS = {EpisodeMap.PAPER: 2, EpisodeMap.HOUSE_A: 3, EpisodeMap.HOUSE_B: 3}
"""How many items an episode on each map of :data:`MAPS` has."""

PREFIX = "gen-"
"""Every generated episode's name starts with this, so it can never be mistaken for a
bundled scenario (``paper-1``) or get its ground truth."""


def episode_name(map_name: str, seed: int) -> str:
    """The name of the generated episode of ``seed`` on ``map_name``: ``gen-paper-s1``."""
    return f"{PREFIX}{map_name}-s{seed}"


def map_of(episode: str) -> str:
    """The map a generated episode's name says it was drawn on (``gen-paper-s1`` -> ``paper``)."""
    if not episode.startswith(PREFIX) or "-s" not in episode:
        raise ValueError(f"{episode!r} is not the name of a generated episode ({PREFIX}<map>-s<seed>)")
    return episode[len(PREFIX) :].rsplit("-s", 1)[0]


def write_house_episode(
    directory: Path,
    rooms: int,
    items: int,
    seed: int,
    spec: EpisodeSpec = DEFAULT_EPISODE,
    *,
    people: int = 2,
) -> Path:
    """Write a house of ``rooms`` rooms, each with an item spot, and a random episode with
    ``items`` items and ``people`` people on it, drawn as ``spec`` says (the scaling family of
    ``toyroom bench``); return its path (``spec.autonomy``:
    :func:`~sim2d.generation.overrides.with_autonomy`)."""
    if rooms < 2:
        raise ValueError(f"a house has at least 2 rooms, not {rooms}")
    directory.mkdir(parents=True, exist_ok=True)
    map_name = f"house-{rooms}r{items}i"
    map_path = directory / f"{PREFIX}{map_name}.map.toml"
    map_path.write_text(house_map(map_name, rooms, rooms, seed))
    name = episode_name(map_name, seed)
    path = directory / f"{name}.toml"
    text = episode(name, map_path.name, map_path, items, seed, spec, people=people)
    path.write_text(with_autonomy(text, parse_overrides(spec.autonomy), path))
    return path


def write_episode(
    directory: Path,
    map_name: str,
    seed: int,
    spec: EpisodeSpec = DEFAULT_EPISODE,
    day: int | None = None,
    morning: Morning | None = None,
) -> Path:
    """Write a random episode (and its generated map) into ``directory``, drawn as ``spec``
    says; return its path (``spec.autonomy``: settings of its ``[autonomy]`` table to
    override, :func:`~sim2d.generation.overrides.with_autonomy`).

    ``day``: the episode is that day of the household of ``seed`` (:mod:`.households`), named
    ``<episode>-d<day>``; every day after the first needs the end of the day before
    (``morning``)."""
    directory.mkdir(parents=True, exist_ok=True)
    if map_name not in MAPS:
        raise ValueError(f"no map {map_name!r}: one of {', '.join(MAPS)}")
    which = EpisodeMap(map_name)
    house = HOUSES.get(which)
    if house is None:
        map_ref, map_path = map_name, SCENARIO_DIR / f"{map_name}.map.toml"
    else:
        map_path = directory / f"{PREFIX}{map_name}.map.toml"
        map_ref = map_path.name
        if not map_path.exists():
            map_path.write_text(house_map(map_name, *house))
    household = episode_name(map_name, seed)
    name = household if day is None else f"{household}-d{day}"
    path = directory / f"{name}.toml"

    def draw(of: int, start: Morning | None = None) -> str:
        return episode(name, map_ref, map_path, ITEMS[which], of, spec, morning=start)

    if day is None:
        text = draw(seed)
    elif day == 1:
        text = draw(seed) + "\n" + "\n".join(household_lines(household, 1))
    else:
        if morning is None:
            raise ValueError(f"day {day} of household {household} needs the end of day {day - 1} (a morning)")
        first_day = draw(seed)
        first = first_morning(first_day, map_path)
        goals = [*first.items, *(["out"] if spec.kind != EpisodeKind.TASKS else [])]
        spots = [loc.id for loc in load_map(str(map_path)).locations]
        check_morning(morning, household, map_name, first_day, spots, goals)
        people = sorted(morning.favourites) or ["A1", "A2"]
        after, changes = night(morning, first, spots, people, goals, seed, day)
        text = draw(day_seed(seed, day), after) + "\n" + "\n".join(household_lines(household, day, changes))
    path.write_text(with_autonomy(text, parse_overrides(spec.autonomy), path))
    return path


def first_morning(text: str, map_path: Path) -> Morning:
    """Where the items of a household's first day (its episode's TOML ``text``) rest."""
    data = tomllib.loads(text)
    return Morning(items={item["id"]: item["at"] for item in data.get("items", [])})
