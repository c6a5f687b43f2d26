"""Generated houses: ``rooms`` rooms of 3 x 3 cells in two rows, joined by doors (a random
spanning tree plus one extra door), an outside below the first room; ``spots`` of the rooms get
an item spot (half of them play spots), and each room sees its own spot plus, at random, that of
one neighbour it has a door to (an open doorway). TOML text in the bundled maps' format."""

from __future__ import annotations

import numpy as np

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
