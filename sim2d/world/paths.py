"""Shortest paths over walkable cells (4-neighbour moves, each costing one step).

A* with the Manhattan distance; ties are broken the same way every time (by cell order),
so the same start and goal always give the same path.
"""

from __future__ import annotations

import heapq
from collections import deque
from collections.abc import Collection, Iterable

from protocol import NEIGHBOURS, GridCell


def shortest_path(walkable: Collection[GridCell], start: GridCell, goal: GridCell) -> list[GridCell] | None:
    """Cells from ``start`` (excluded) to ``goal`` (included); ``[]`` when already there;
    ``None`` when ``goal`` cannot be reached (or is not walkable)."""
    if goal not in walkable or start not in walkable:
        return None
    if start == goal:
        return []
    came_from: dict[GridCell, GridCell] = {}
    cost = {start: 0}
    frontier: list[tuple[int, int, GridCell]] = [(_manhattan(start, goal), 0, start)]
    while frontier:
        _, steps, cell = heapq.heappop(frontier)
        if cell == goal:
            return _unwind(came_from, start, goal)
        if steps > cost[cell]:
            continue
        for nxt in _neighbours(cell, walkable):
            if steps + 1 < cost.get(nxt, 1 << 30):
                cost[nxt] = steps + 1
                came_from[nxt] = cell
                heapq.heappush(frontier, (steps + 1 + _manhattan(nxt, goal), steps + 1, nxt))
    return None


def path_to_any(
    walkable: Collection[GridCell], start: GridCell, goals: Iterable[GridCell]
) -> list[GridCell] | None:
    """Shortest path from ``start`` to the nearest of ``goals`` (breadth first)."""
    targets = set(goals)
    if start in targets:
        return []
    came_from: dict[GridCell, GridCell] = {}
    seen = {start}
    queue = deque([start])
    while queue:
        cell = queue.popleft()
        for nxt in _neighbours(cell, walkable):
            if nxt in seen:
                continue
            seen.add(nxt)
            came_from[nxt] = cell
            if nxt in targets:
                return _unwind(came_from, start, nxt)
            queue.append(nxt)
    return None


def _neighbours(cell: GridCell, walkable: Collection[GridCell]) -> list[GridCell]:
    return [(cell[0] + dc, cell[1] + dr) for dc, dr in NEIGHBOURS if (cell[0] + dc, cell[1] + dr) in walkable]


def _manhattan(a: GridCell, b: GridCell) -> int:
    return abs(a[0] - b[0]) + abs(a[1] - b[1])


def _unwind(came_from: dict[GridCell, GridCell], start: GridCell, goal: GridCell) -> list[GridCell]:
    path = [goal]
    while path[-1] != start:
        path.append(came_from[path[-1]])
    path.pop()
    path.reverse()
    return path
