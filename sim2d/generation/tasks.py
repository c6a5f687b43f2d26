"""Task episodes (``--kind tasks``): the two people of an episode built around one of the
robot's jobs (:data:`TASKS`), as ``[[agents]]`` lines of the scenario file.

The owner of the item a task is about starts beside it and knows where it is (``knows``:
they left it there, whatever the episode's minds), then goes on an errand outside. In
``moved`` and ``hidden`` the other person moves the item while the owner is away, timed to
land shortly before the owner is back (``move_after``, from walking times on the map): a
false belief the owner acts on as soon as they return, which the robot can put right only
if it notices. In ``told``, ``overlooked`` and ``stale`` nothing is moved: the owner comes to
believe a wrong place in a way the robot cannot see (a word out of its hearing, an item in
plain view they fail to notice, a belief from before the episode), and only their walk there
shows it (:func:`belief_agents`).
"""

from __future__ import annotations

import math
from collections.abc import Collection, Sequence

import numpy as np

from protocol import GridCell, Location, TaskKind, task_of
from protocol.carry import walking_distances

from ..scenario.maps import GameMap
from ..world.paths import shortest_path
from ..world.world import PERSON_SPEED

TASKS = TaskKind.names()
"""The jobs task episodes are built around, in turn by seed (:func:`protocol.task_of`): the
names of :class:`protocol.TaskKind`, which says what each is. ``moved``, ``hidden``,
``contested`` and ``seen`` are built around a move (or a want) the robot can see; in the
other three (:data:`BELIEF_TASKS`) behaviour is the evidence."""
BELIEF_TASKS = tuple(kind.value for kind in (TaskKind.TOLD, TaskKind.OVERLOOKED, TaskKind.STALE))
"""The kinds of :data:`TASKS` whose false belief only behaviour shows (:func:`belief_agents`)."""
TELL_AFTER = (5, 30)
"""When the telling of ``told`` happens (ticks, drawn uniformly)."""
WATCH_TICKS = (20, 60)
"""How long the owner of ``overlooked`` stands in view of the item first (ticks)."""


ERRAND_TICKS = (80, 200)
"""How long the owner's errand keeps them outside (ticks, drawn uniformly)."""
LEAD_TICKS = (10, 60)
"""How long before the owner starts back from the errand the moved item lands (ticks, drawn
uniformly): shortly before they come back for it."""
HANDLING_TICKS = 10
"""Ticks a take and a drop add to the mover's walk (a margin, not a measurement)."""


def seed_of(kind: str, nth: int = 0, kinds: Sequence[str] = TASKS) -> int:
    """The ``nth`` smallest seed whose episode :func:`task_of` builds around ``kind``."""
    seeds = (seed for seed in range(10**6) if task_of(seed, kinds) == kind)
    for _ in range(nth):
        next(seeds)
    return next(seeds)


def check_kinds(kinds: Sequence[str]) -> tuple[TaskKind, ...]:
    """``kinds`` (names of :data:`TASKS`) as their :class:`~protocol.TaskKind` values, in order
    (raises ``ValueError`` naming a bad one)."""
    bad = [kind for kind in kinds if kind not in TASKS]
    if bad or not kinds:
        raise ValueError(f"task kinds are some of {', '.join(TASKS)}, not {', '.join(bad) or 'none'}")
    return tuple(TaskKind(kind) for kind in kinds)


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
    kinds: Sequence[str] = TASKS,
) -> list[str]:
    """The two people of a task episode, as ``[[agents]]`` lines (the first item is the one
    the task is about; ``homes``: cells to start from when the task does not fix one;
    ``search``: how the episode's people look for things, for ``hidden``; ``kinds``: the
    task kinds drawn from, in turn by seed)."""
    rng = np.random.default_rng([seed, 2])
    task, items = task_of(seed, kinds), list(placed)
    wanted = items[0]
    spot = next(loc for loc in game_map.locations if loc.id == placed[wanted])
    if task in BELIEF_TASKS:
        return belief_agents(task, game_map, placed, homes, rng)
    if task == TaskKind.CONTESTED.value:
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
    if task == TaskKind.SEEN.value and in_view:
        target = in_view[int(rng.integers(len(in_view)))]
        owner.append(f"errand_after = {int(rng.integers(150, 251))}")
        after = 0
    else:
        order = [loc for loc in search_order(game_map, spot, search) if loc in unseen]
        hidden = task == TaskKind.HIDDEN.value
        target = (order or unseen)[-1] if hidden else unseen[int(rng.integers(len(unseen)))]
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
    """The scenario-file lines of an autonomous person ``person`` living at ``home`` (then ``extra``)."""
    return [
        "[[agents]]",
        f'id = "{person}"',
        'kind = "person"',
        "autonomous = true",
        f"home = [{home[0]}, {home[1]}]",
        *extra,
        "",
    ]


def belief_agents(
    task: str, game_map: GameMap, placed: dict[str, str], homes: list[GridCell], rng: np.random.Generator
) -> list[str]:
    """The two people of a ``told``, ``overlooked`` or ``stale`` episode (:data:`TASKS`): the
    owner (A1) wants the first item and comes to be sure it is at a wrong place, out of their
    view, without anything being moved; A2 wants the other item and starts sure of a wrong
    place for it too (a belief from before the episode), so each episode shows two. Starts and
    wrong places are chosen so that the walk there shows the belief for long
    (:func:`revealing`)."""
    items = list(placed)
    wanted = items[0]
    cells = sorted(c for c in game_map.region_of if c not in {_cell(loc) for loc in game_map.locations})
    inside = [c for c in cells if game_map.region_of[c] not in game_map.outside_regions]
    pool = cells if task == TaskKind.STALE.value else inside  # stale: coming in from outside, or already in
    occupied = set(placed.values())
    overlooked = task == TaskKind.OVERLOOKED.value
    owner_home, target = revealing(game_map, pool, placed[wanted], rng, overlooked, occupied)
    owner, others = [f'prefers = "{wanted}"'], [c for c in inside if c != owner_home]
    mover: list[str] = []
    if task == TaskKind.TOLD.value:
        after = int(rng.integers(TELL_AFTER[0], TELL_AFTER[1] + 1))
        region = game_map.region_of[owner_home]
        others = [c for c in others if game_map.region_of[c] == region] or [owner_home]
        owner += [f'knows = ["{wanted}"]', f"wait = {after + 10}"]
        mover += [f'tell = ["A1", "{wanted}"]', f"tell_after = {after}", f"wait = {after + 1}"]
    elif task == TaskKind.OVERLOOKED.value:
        watch = int(rng.integers(WATCH_TICKS[0], WATCH_TICKS[1] + 1))
        owner += [f'believes = [["{wanted}", "{target}"]]', f'overlooks = ["{wanted}"]', f"wait = {watch}"]
    else:
        owner += [f'believes = [["{wanted}", "{target}"]]']
    believes = [(wanted, target)] if task == TaskKind.TOLD.value else []
    other_home = _draw(others, rng)
    if len(items) > 1:
        other_home, wrong = revealing(game_map, others, placed[items[1]], rng, occupied=occupied)
        believes.append((items[1], wrong))
    if believes:
        mover.append("believes = [" + ", ".join(f'["{i}", "{loc}"]' for i, loc in believes) + "]")
    other = items[1] if len(items) > 1 else "out"
    return [
        *person_lines("A1", owner_home, *owner),
        *person_lines("A2", other_home, f'prefers = "{other}"', *mover),
    ]


def revealing(
    game_map: GameMap,
    pool: Sequence[GridCell],
    truth: str,
    rng: np.random.Generator,
    overlooked: bool = False,
    occupied: Collection[str] = (),
) -> tuple[GridCell, str]:
    """A start among ``pool`` and a wrong place for an item resting at ``truth`` whose walk
    there shows the wrong belief for long: the cells walked before the wrong place comes into
    view (or the item itself, unless it is overlooked); drawn among the pairs within 70% of
    the best (of up to 24 starts). An overlooked item is in view at the start. Places in
    ``occupied`` (where other items rest) are avoided where there are others: a walk to
    another item reads as wanting that item, not as a false belief."""
    starts = [pool[int(i)] for i in rng.choice(len(pool), size=min(len(pool), 24), replace=False)]
    options = []
    for home in starts:
        view = game_map.sees.get(home, ())
        if (truth in view) != overlooked:
            continue
        empty = [loc for loc in game_map.locations if loc.id not in occupied] or game_map.locations
        for loc in empty:
            if loc.id != truth and loc.id not in view:
                options.append((_shown(game_map, home, loc, truth, overlooked), home, loc.id))
    if not options:
        home = _draw(pool, rng)
        return home, _wrong_place(game_map, home, truth, rng)
    best = max(score for score, _, _ in options)
    good = [(home, target) for score, home, target in options if score >= 0.7 * best]
    return good[int(rng.integers(len(good)))]


def _shown(game_map: GameMap, home: GridCell, target: Location, truth: str, overlooked: bool) -> int:
    """Steps of the walk from ``home`` towards ``target`` that take the walker further from
    ``truth`` (where the item is: steps nobody heading there would take, so they show the
    belief), before ``target`` (or, unless the item is overlooked, ``truth``) comes into view."""
    spot = next(_cell(loc) for loc in game_map.locations if loc.id == truth)
    far = walking_distances(game_map.walkable, [spot])
    path, shown, before = shortest_path(game_map.walkable, home, _cell(target)) or [], 0, far.get(home, 0)
    for cell in path:
        view = game_map.sees.get(cell, ())
        if target.id in view or (not overlooked and truth in view):
            break
        shown += far.get(cell, 0) > before
        before = far.get(cell, 0)
    return shown


def _draw(cells: Sequence[GridCell], rng: np.random.Generator) -> GridCell:
    return cells[int(rng.integers(len(cells)))]


def _wrong_place(game_map: GameMap, home: GridCell, truth: str, rng: np.random.Generator) -> str:
    """A location other than ``truth``, out of view from ``home`` where there is one."""
    view = set(game_map.sees.get(home, ()))
    others = [loc.id for loc in game_map.locations if loc.id != truth]
    hidden = [loc for loc in others if loc not in view]
    choices = hidden or others
    return choices[int(rng.integers(len(choices)))]
