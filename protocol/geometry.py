"""Geometric value types shared by the messages.

Units: positions in metres in the engine's world frame (x to the right, y up), angles in
radians counter-clockwise from +x, velocities in metres per second. Grid cells are integer
``(col, row)`` pairs; cell ``(c, r)`` covers ``[origin.x + c*cell_size, origin.x + (c+1)*cell_size)``
by ``[origin.y + r*cell_size, origin.y + (r+1)*cell_size)``.
"""

from __future__ import annotations

from typing import Annotated

import msgspec

NonNegInt = Annotated[int, msgspec.Meta(ge=0)]

GridCell = tuple[int, int]
"""A grid cell as a plain ``(col, row)`` pair (for sets, dicts and arithmetic)."""

NEIGHBOURS: tuple[GridCell, ...] = ((1, 0), (-1, 0), (0, 1), (0, -1))
"""The 4-neighbourhood as ``(dcol, drow)`` steps: the cells a body can step to, the cells a
door must touch, and "next to" for speech and hand-overs."""


class Cell(msgspec.Struct, frozen=True):
    """A grid cell: integer column (along +x) and row (along +y), both >= 0."""

    col: NonNegInt
    row: NonNegInt


class Vec2(msgspec.Struct, frozen=True):
    """A 2D vector: metres for positions, metres per second for velocities."""

    x: float
    y: float


class Pose(msgspec.Struct, frozen=True):
    """A body's pose: position ``(x, y)`` in metres and heading ``theta`` in radians."""

    x: float
    y: float
    theta: float = 0.0
