"""Task episodes (``--kind tasks``): the two people of an episode built around one of the
robot's jobs (:data:`TASKS`), as ``[[agents]]`` lines of the scenario file."""

from __future__ import annotations

import numpy as np

from protocol import GridCell

from .maps import GameMap

TASKS = ("moved", "hidden", "contested", "seen")
"""The jobs task episodes are built around, in turn by seed: ``moved`` (while its owner is on
an errand, someone moves the item they will come back for to a spot out of the owner's view),
``hidden`` (the same, to the unseen spot farthest from where it was: the last place they would
look), ``contested`` (both people want the same item) and ``seen`` (Sally-Anne's true-belief
control: the owner watches the item being moved to a spot in view, then goes on the errand;
putting it back would mislead them)."""


def task_of(seed: int) -> str:
    """The job a task episode of ``seed`` is built around."""
    return TASKS[seed % len(TASKS)]


def task_agents(game_map: GameMap, placed: dict[str, str], homes: list[GridCell], seed: int) -> list[str]:
    """The two people of a task episode, as ``[[agents]]`` lines (the first item is the one
    the task is about; ``homes``: cells to start from when the task does not fix one)."""
    rng = np.random.default_rng([seed, 2])
    task, items = task_of(seed), list(placed)
    wanted = items[0]
    spot = next(loc for loc in game_map.locations if loc.id == placed[wanted])
    if task == "contested":
        return [
            line
            for person, home in zip(("A1", "A2"), homes[:2], strict=True)
            for line in person_lines(person, home, f'prefers = "{wanted}"')
        ]
    region = game_map.region_of[(spot.cell.col, spot.cell.row)]
    spots = {(loc.cell.col, loc.cell.row) for loc in game_map.locations}
    cells = sorted(
        c for c, r in game_map.region_of.items() if r == region and c not in spots and c != homes[2]
    )
    owner_home = cells[int(rng.integers(len(cells)))] if cells else homes[0]
    seen = set(game_map.sees.get(owner_home, ())) | {spot.id}
    unseen = [loc for loc in game_map.locations if loc.id not in seen] or [
        loc for loc in game_map.locations if loc.id != spot.id
    ]
    in_view = [loc for loc in game_map.locations if loc.id in seen and loc.id != spot.id]
    watch: tuple[str, ...] = ()
    if task == "seen" and in_view:
        target = in_view[int(rng.integers(len(in_view)))]
        watch = (f"errand_after = {int(rng.integers(150, 251))}",)
    elif task == "hidden":
        target = max(
            unseen, key=lambda loc: abs(loc.cell.col - spot.cell.col) + abs(loc.cell.row - spot.cell.row)
        )
    else:
        target = unseen[int(rng.integers(len(unseen)))]
    other = items[1] if len(items) > 1 else "out"
    mover_home = next(h for h in homes if h != owner_home)
    return [
        *person_lines(
            "A1", owner_home, f'prefers = "{wanted}"', f"errand = {int(rng.integers(80, 201))}", *watch
        ),
        *person_lines("A2", mover_home, f'prefers = "{other}"', f'move = ["{wanted}", "{target.id}"]'),
    ]


def person_lines(person: str, home: GridCell, *extra: str) -> list[str]:
    return [
        "[[agents]]",
        f'id = "{person}"',
        'kind = "person"',
        "autonomous = true",
        f"home = [{home[0]}, {home[1]}]",
        *extra,
        "",
    ]
