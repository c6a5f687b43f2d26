"""Wall segments from a grid: every edge between a walkable cell and a wall cell (or the
grid's border), merged into maximal straight runs. Door cells are walkable, so doors are
gaps in the walls."""

from __future__ import annotations

from collections.abc import Collection

from protocol import GridCell

Segment = tuple[tuple[float, float], tuple[float, float]]


def wall_segments(walkable: Collection[GridCell], cell_size: float) -> list[Segment]:
    """Segments ``((x0, y0), (x1, y1))`` in metres, sorted, horizontal runs first."""
    horizontal: dict[int, list[int]] = {}  # y (in cells) -> x of unit edges
    vertical: dict[int, list[int]] = {}  # x (in cells) -> y of unit edges
    for col, row in walkable:
        if (col, row - 1) not in walkable:
            horizontal.setdefault(row, []).append(col)
        if (col, row + 1) not in walkable:
            horizontal.setdefault(row + 1, []).append(col)
        if (col - 1, row) not in walkable:
            vertical.setdefault(col, []).append(row)
        if (col + 1, row) not in walkable:
            vertical.setdefault(col + 1, []).append(row)
    segments: list[Segment] = []
    for y, xs in sorted(horizontal.items()):
        for start, end in _runs(xs):
            segments.append(((start * cell_size, y * cell_size), (end * cell_size, y * cell_size)))
    for x, ys in sorted(vertical.items()):
        for start, end in _runs(ys):
            segments.append(((x * cell_size, start * cell_size), (x * cell_size, end * cell_size)))
    return segments


def _runs(units: list[int]) -> list[tuple[int, int]]:
    """Unit intervals ``[u, u+1]`` merged into maximal runs ``(start, end)``."""
    runs: list[tuple[int, int]] = []
    for u in sorted(set(units)):
        if runs and runs[-1][1] == u:
            runs[-1] = (runs[-1][0], u + 1)
        else:
            runs.append((u, u + 1))
    return runs
