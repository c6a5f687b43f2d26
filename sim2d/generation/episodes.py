"""Random episodes: scenario (and map) files made from a seed.

- :func:`house_map`: a house of ``rooms`` rooms of 3 x 3 cells in two rows, joined by
  doors (a random spanning tree plus one extra door), an outside below the first room;
  ``spots`` of the rooms get an item spot (half of them play spots), and each room sees its
  own spot plus, at random, that of one neighbour it has a door to (an open doorway).
- :func:`episode`: a scenario on a map: items at random spots, two autonomous people with
  hidden preferences drawn from the seed, random mischief and patience, an acting robot.

Everything is TOML text in the same format as the bundled files, so any engine that reads
those (sim2d, the grid engine) plays them.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from protocol import EpisodeKind, Minds

from ..scenario.maps import SCENARIO_DIR, load_map
from .overrides import with_autonomy
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


Edge = tuple[int, int, int, int, int, int]
"""A door between rooms: (room a, room b, a's grid column, a's grid row, dx, dy)."""


def _col0(gx: int) -> int:
    return 4 * gx  # 3 cells of room, 1 of wall


def _row0(gy: int) -> int:
    return 4 + 4 * gy  # the outside below


def _doors(rng: np.random.Generator, grid: dict[tuple[int, int], int], rooms: int) -> list[Edge]:
    """A random spanning tree of the rooms' neighbour graph, plus one extra door."""
    edges: list[Edge] = []
    for (gx, gy), index in grid.items():
        for dx, dy in ((1, 0), (0, 1)):
            other = grid.get((gx + dx, gy + dy))
            if other is not None:
                edges.append((index, other, gx, gy, dx, dy))
    order = rng.permutation(len(edges))
    parent = list(range(rooms))

    def find(i: int) -> int:
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    doors, spare = [], []
    for e in order:
        a, b = edges[e][0], edges[e][1]
        if find(a) != find(b):
            parent[find(a)] = find(b)
            doors.append(edges[e])
        else:
            spare.append(edges[e])
    return doors + spare[:1]


def _room_lines(grid: dict[tuple[int, int], int], with_spot: list[int], play: set[int]) -> list[str]:
    lines: list[str] = []
    for (gx, gy), index in sorted(grid.items(), key=lambda kv: kv[1]):
        kind = "playground" if index in play else "storage" if index in with_spot else "room"
        lines += [
            "[[regions]]",
            f'id = "R{index}"',
            f'kind = "{kind}"',
            f"rects = [[{_col0(gx)}, {_row0(gy)}, 3, 3]]",
            "",
        ]
    return lines + ["[[regions]]", 'id = "O"', 'kind = "outside"', "rects = [[0, 0, 3, 3]]", ""]


def _door_lines(doors: list[Edge]) -> list[str]:
    lines: list[str] = []
    for a, b, gx, gy, dx, _dy in doors:
        cell = (_col0(gx) + 3, _row0(gy) + 1) if dx else (_col0(gx) + 1, _row0(gy) + 3)
        lines += [
            "[[doors]]",
            f'id = "R{a}-R{b}"',
            f"cell = [{cell[0]}, {cell[1]}]",
            f'joins = ["R{a}", "R{b}"]',
            "",
        ]
    return lines + ["[[doors]]", 'id = "R0-O"', "cell = [1, 3]", 'joins = ["R0", "O"]', ""]


def _spot_lines(grid: dict[tuple[int, int], int], with_spot: list[int], play: set[int]) -> list[str]:
    lines: list[str] = []
    for index in with_spot:
        gx, gy = next(k for k, v in grid.items() if v == index)
        lines += [
            "[[locations]]",
            f'id = "L{index}"',
            f'region = "R{index}"',
            f"cell = [{_col0(gx) + 1}, {_row0(gy) + 1}]",
            f"play = {'true' if index in play else 'false'}",
            "",
        ]
    return lines


def _visibility_lines(rng: np.random.Generator, rooms: int, doors: list[Edge]) -> list[str]:
    """Each room sees its own spot and, at random, that of one room it has a door to."""
    neighbours: dict[int, list[int]] = {i: [] for i in range(rooms)}
    for a, b, *_ in doors:
        neighbours[a].append(b)
        neighbours[b].append(a)
    lines: list[str] = []
    for index in range(rooms):
        sees = {index}
        if neighbours[index] and rng.random() < 0.5:
            sees.add(int(rng.choice(neighbours[index])))
        lines += [
            "[[visibility]]",
            f'from = ["R{index}"]',
            "sees = [" + ", ".join(f'"R{i}"' for i in sorted(sees)) + "]",
            "",
        ]
    return lines + ["[[visibility]]", 'from = ["O"]', 'sees = ["O"]', ""]


def house_map(name: str, rooms: int, spots: int, seed: int) -> str:
    """The TOML text of a random house."""
    rng = np.random.default_rng(seed)
    per_row = (rooms + 1) // 2
    grid = {(index % per_row, index // per_row): index for index in range(rooms)}
    doors = _doors(rng, grid, rooms)
    with_spot = sorted(rng.choice(rooms, size=min(spots, rooms), replace=False).tolist())
    play = set(with_spot[: max(1, len(with_spot) // 2)])
    lines = [
        f"# A generated house (seed {seed}): {rooms} rooms, {len(with_spot)} item spots.",
        f'name = "{name}"',
        "cell_size = 1.0",
        f"columns = {4 * per_row - 1}",
        f"rows = {4 + 4 * 2 - 1}",
        "",
    ]
    lines += _room_lines(grid, with_spot, play) + _door_lines(doors) + _spot_lines(grid, with_spot, play)
    return "\n".join(lines + _visibility_lines(rng, rooms, doors))


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
        f"hearsay = {rng.uniform(0.01, 0.05):.4f}",
        f'search = "{("likely", "nearest")[int(rng.integers(2))]}"',
        f"wander = {rng.uniform(0.0, 0.15):.3f}",
        f"replan = {rng.uniform(0.0, 0.02):.4f}",
        f"knows = {rng.uniform(0.3, 0.7):.3f}",
        f"stale = {rng.uniform(0.1, 0.3):.3f}",
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
    *,
    max_ticks: int = 1500,
    minds: str = "simple",
    kind: str = "everyday",
    people: int = 2,
    tasks: Sequence[str] | None = None,
) -> str:
    """The TOML text of a random episode on the map at ``map_path``, which the file names as
    ``map_ref`` (a bundled map's name, or a file name beside the episode: no absolute paths,
    so a folder of episodes can be moved or shared); ``minds``: one of :data:`MINDS`;
    ``kind``: one of :data:`KINDS`; ``people``: how many (everyday episodes; people past the
    second get homes of their own draw, so the first two's episode is the same); ``tasks``:
    the task kinds a ``tasks`` episode is drawn from (default: all of
    :data:`~sim2d.generation.tasks.TASKS`)."""
    if people < 1 or (kind == "tasks" and people != 2):
        raise ValueError(f"an episode has at least 1 person (tasks: 2), not {people}")
    if minds not in MINDS:
        raise ValueError(f"minds must be one of {', '.join(MINDS)}, not {minds!r}")
    if kind not in KINDS:
        raise ValueError(f"kind must be one of {', '.join(KINDS)}, not {kind!r}")
    rng = np.random.default_rng(seed)
    game_map = load_map(str(map_path))
    rich = rich_autonomy(seed) if minds == "rich" else []
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
        'robot = "act"',
        f"tick_seconds = {TICK_SECONDS}",
        f"max_ticks = {max_ticks}",
        "",
        "[autonomy]",
        f"switch = {rng.uniform(0.0005, 0.002) * (kind != 'tasks'):.5f}",
        f"mischief = {rng.uniform(0.05, 0.3) * (kind != 'tasks'):.3f}",
        f"put_away = {rng.uniform(0.3, 0.8) * (kind != 'tasks'):.3f}",
        "play_ticks = [60, 200]",
        "wait_ticks = [20, 60]",
        *rich,
        *(['planner = "model"'] if minds == "model" else []),
        "",
    ]
    if not 1 <= items <= len(ITEM_SHAPES):
        raise ValueError(f"an episode has 1 to {len(ITEM_SHAPES)} items, not {items}")
    placed: dict[str, str] = {}
    for k in range(items):
        item, shape = ITEM_SHAPES[k]
        placed[item] = spots[int(rng.integers(len(spots)))]
        lines += ["[[items]]", f'id = "{item}"', f'shape = "{shape}"', f'at = "{placed[item]}"', ""]
    if kind == "tasks":
        kinds = TASKS if tasks is None else check_kinds(tasks)
        lines += task_agents(
            game_map, placed, homes, seed, tick_seconds=TICK_SECONDS, search=search, kinds=kinds
        )
    else:
        more = np.random.default_rng([seed, 1]).choice(len(cells), size=max(0, people - 2))
        for n, home in enumerate([*homes[: min(people, 2)], *(cells[int(i)] for i in more)]):
            lines += person_lines(f"A{n + 1}", home)
    lines += ["[[agents]]", 'id = "robot"', 'kind = "robot"', f"home = [{homes[2][0]}, {homes[2][1]}]", ""]
    return "\n".join(lines)


MAPS = {
    "paper": None,
    "house-a": (5, 4, 11),
    "house-b": (6, 4, 23),
}
"""The maps episodes are drawn on: the paper's, and two generated houses (rooms, spots, seed)."""

ITEMS = {"paper": 2, "house-a": 3, "house-b": 3}


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
    max_ticks: int = 1500,
    minds: str = "simple",
    kind: str = "everyday",
    people: int = 2,
    tasks: Sequence[str] | None = None,
    autonomy: Mapping[str, str] | None = None,
) -> Path:
    """Write a house of ``rooms`` rooms, each with an item spot, and a random episode with
    ``items`` items and ``people`` people on it (the scaling family of ``toyroom bench``);
    return its path (``autonomy``: :func:`~sim2d.generation.overrides.with_autonomy`)."""
    if rooms < 2:
        raise ValueError(f"a house has at least 2 rooms, not {rooms}")
    directory.mkdir(parents=True, exist_ok=True)
    map_name = f"house-{rooms}r{items}i"
    map_path = directory / f"{PREFIX}{map_name}.map.toml"
    map_path.write_text(house_map(map_name, rooms, rooms, seed))
    name = episode_name(map_name, seed)
    path = directory / f"{name}.toml"
    text = episode(
        name,
        map_path.name,
        map_path,
        items,
        seed,
        max_ticks=max_ticks,
        minds=minds,
        kind=kind,
        people=people,
        tasks=tasks,
    )
    path.write_text(with_autonomy(text, autonomy or {}, path))
    return path


def write_episode(
    directory: Path,
    map_name: str,
    seed: int,
    max_ticks: int = 1500,
    minds: str = "simple",
    kind: str = "everyday",
    tasks: Sequence[str] | None = None,
    autonomy: Mapping[str, str] | None = None,
) -> Path:
    """Write a random episode (and its generated map) into ``directory``; return its path
    (``tasks``: the task kinds of a ``tasks`` episode, default all; ``autonomy``: settings of
    its ``[autonomy]`` table to override, :func:`~sim2d.generation.overrides.with_autonomy`)."""
    directory.mkdir(parents=True, exist_ok=True)
    spec = MAPS[map_name]
    if spec is None:
        map_ref, map_path = map_name, SCENARIO_DIR / f"{map_name}.map.toml"
    else:
        map_path = directory / f"{PREFIX}{map_name}.map.toml"
        map_ref = map_path.name
        if not map_path.exists():
            map_path.write_text(house_map(map_name, *spec))
    name = episode_name(map_name, seed)
    path = directory / f"{name}.toml"
    text = episode(
        name,
        map_ref,
        map_path,
        ITEMS[map_name],
        seed,
        max_ticks=max_ticks,
        minds=minds,
        kind=kind,
        tasks=tasks,
    )
    path.write_text(with_autonomy(text, autonomy or {}, path))
    return path
