"""The world model built from a protocol scene: cells, item locations, possible worlds and
what each cell sees.

Shapes: ``C`` walkable cells, ``L`` item locations, ``K`` items, ``V = 2L`` values per item
(``v = 2*l + held``: resting at location ``l``, or held by someone else near ``l``; the
encoding of :mod:`protocol.itemvalue`, re-exported here), and ``W = V**K``
possible worlds. Everything is numpy arrays indexed by these integers.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property

import numpy as np

from protocol import RegionKind, Scene
from protocol.carry import CarrierSight, carry_locations, location_distances
from protocol.itemvalue import HELD as HELD
from protocol.itemvalue import RESTING as RESTING
from protocol.itemvalue import VALUES_PER_LOCATION as VALUES_PER_LOCATION
from protocol.itemvalue import held_value as held_value
from protocol.itemvalue import is_held as is_held
from protocol.itemvalue import is_resting as is_resting
from protocol.itemvalue import location_of as location_of
from protocol.itemvalue import value_of as value_of

from .arrays import BoolArray, IntArray

ABSENT = "absent"
"""The location of an item that is not in the scene (``ItemSpec.absent``)."""

MOVE_STEPS = ((0, 1), (0, -1), (-1, 0), (1, 0))
"""The cell step of each move action, in action-index order (``Move.UP``, ``DOWN``, ``LEFT``,
``RIGHT``) as (d col, d row); rows grow upwards. The planner's alphabet, not the
4-neighbourhood (:data:`protocol.NEIGHBOURS`)."""


@dataclass(frozen=True)
class WorldModel:
    """Everything about a scene the model needs, as integer-indexed arrays.

    Attributes:
        cells: ``(C, 2)`` walkable cells (col, row), sorted.
        neighbour: ``(C, 4)`` index of the cell Up/Down/Left/Right, or -1 (a wall).
        outside: ``(C,)`` whether the cell is in an outside region.
        spot_at: ``(C,)`` index of the location on the cell, or -1.
        play_at: ``(C,)`` whether the cell is a play spot.
        nearest: ``(C,)`` the location a carried item counts as being at: the nearest
            location of the cell's region, or the nearest of all for regions with none.
        sees: ``(C, L)`` whether a location is visible from a cell.
        locations: ``L`` location ids; items: ``K`` item ids. When the scene has an
            ``absent`` item, the last location is :data:`ABSENT`: never seen, on no cell.
        distance: ``(L, C)`` path length in cells from each location to every cell.
        use_at: ``(C,)`` whether the cell is a place where items are used in place.
        capacity: ``(L,)`` how many items may rest at each location (0: any number).
        carrier_spot: ``(C,)`` the location whose sight shows someone carrying an item on the
            cell, or -1 (:class:`protocol.carry.CarrierSight`).
        open_areas: ``(C, R)`` the regions without locations that each cell is in or is a
            door of: a carrier there is seen from cells sharing one.
        portable: ``(K,)`` whether each item can be carried (``ItemSpec.portable``): a fixed
            item is never held in any world the model allows (:attr:`value_ok`).
    """

    cells: IntArray
    neighbour: IntArray
    outside: BoolArray
    spot_at: IntArray
    play_at: BoolArray
    nearest: IntArray
    sees: BoolArray
    locations: tuple[str, ...]
    items: tuple[str, ...]
    cell_index: dict[tuple[int, int], int]
    distance: IntArray
    use_at: BoolArray
    capacity: IntArray
    carrier_spot: IntArray
    open_areas: BoolArray
    portable: BoolArray

    @property
    def n_cells(self) -> int:
        return len(self.cells)

    @property
    def n_locations(self) -> int:
        return len(self.locations)

    @property
    def n_items(self) -> int:
        return len(self.items)

    @property
    def n_values(self) -> int:
        return VALUES_PER_LOCATION * len(self.locations)

    @property
    def have_goals(self) -> bool:
        """Whether taking an item is itself a goal ("have it"): in a scene with no play and no
        ``use`` location, where nothing else can be done with an item, ``Take(k)`` ends the
        planner's episode with ``k``'s utility (docs/model.md, "Desires")."""
        return not (bool(self.play_at.any()) or bool(self.use_at.any()))

    @property
    def n_worlds(self) -> int:
        """``W = V**K`` (a Python int: it may be far too many to build)."""
        return int(self.n_values) ** self.n_items

    @cached_property
    def worlds(self) -> IntArray:
        """``(W, K)`` item values of every world, built on first use (the exact model only)."""
        K, V = self.n_items, self.n_values
        if K == 0:
            return np.zeros((1, 0), dtype=np.int64)
        grid = np.stack(np.meshgrid(*[np.arange(V)] * K, indexing="ij"), axis=-1)
        return grid.reshape(-1, K).astype(np.int64)

    @cached_property
    def place(self) -> IntArray:
        """``(W, K)`` location index of every item in every world."""
        return location_of(self.worlds)

    @cached_property
    def strides(self) -> IntArray:
        """``(K,)`` world-index stride of each item: ``w = sum_k worlds[w, k] * strides[k]``."""
        return np.array(
            [self.n_values ** (self.n_items - 1 - k) for k in range(self.n_items)], dtype=np.int64
        )

    @cached_property
    def value_ok(self) -> BoolArray:
        """``(K, V)`` the values each item may take on its own: every value, less "held" for a
        fixed item (``portable`` false) and "held at :data:`ABSENT`" for every item."""
        values = np.arange(self.n_values)
        ok = np.broadcast_to(is_resting(values), (self.n_items, self.n_values)) | self.portable[:, None]
        if self.locations and self.locations[-1] == ABSENT:
            ok = ok & (values != value_of(self.n_locations - 1, held=True))[None, :]
        return np.ascontiguousarray(ok)

    @cached_property
    def allowed(self) -> BoolArray:
        """``(W,)`` the worlds no location's ``capacity`` rules out, with every item at a value
        :attr:`value_ok` allows (no fixed item held, no item held "at" :data:`ABSENT`)."""
        resting = is_resting(self.worlds)
        ok = np.ones(len(self.worlds), dtype=bool)
        for loc in np.flatnonzero(self.capacity > 0):
            ok &= ((self.place == loc) & resting).sum(axis=1) <= self.capacity[loc]
        for k in range(self.n_items):  # K passes over (W,)
            ok &= self.value_ok[k, self.worlds[:, k]]
        return ok

    @cached_property
    def percepts(self) -> dict[tuple[object, ...], object]:
        """Percepts already worked out on this model (:func:`brain.model.belief.percept`), by
        what they were worked out from: the trackers of a brain ask for the same ones tick
        after tick."""
        return {}

    def sees_carrier(self, viewer: int, carriers: IntArray) -> BoolArray:
        """``carriers.shape``: whether a person on cell index ``viewer`` sees someone carrying
        an item on each of ``carriers`` (cell indices): from their own cell, where the
        carrier's location is in view, or in a shared region without locations."""
        carriers = np.asarray(carriers, dtype=np.int64)
        spot = self.carrier_spot[carriers]
        seen = (carriers == viewer) | ((spot >= 0) & self.sees[viewer, np.maximum(spot, 0)])
        return seen | (self.open_areas[carriers] & self.open_areas[viewer]).any(axis=-1)

    def world_index(self, values: IntArray) -> IntArray:
        """World indices of ``(..., K)`` item values."""
        return np.asarray(values, dtype=np.int64) @ self.strides

    def with_value(self, world: IntArray, item: int, value: IntArray | int) -> IntArray:
        """World indices after setting ``item`` to ``value`` in ``world``."""
        old = self.worlds[world, item]
        return world + (np.asarray(value) - old) * self.strides[item]


def build_world_model(scene: Scene) -> WorldModel:
    """The world model of a protocol scene (its items and locations, its walkable cells)."""
    region_of = {(c.col, c.row): r.id for r in scene.regions for c in r.cells}
    outside_regions = {r.id for r in scene.regions if r.kind is RegionKind.OUTSIDE}
    walkable = sorted(set(region_of) | {(d.cell.col, d.cell.row) for d in scene.doors})
    index = {cell: i for i, cell in enumerate(walkable)}
    n = len(walkable)
    neighbour = np.full((n, 4), -1, dtype=np.int64)
    for i, (col, row) in enumerate(walkable):
        for a, (dc, dr) in enumerate(MOVE_STEPS):
            neighbour[i, a] = index.get((col + dc, row + dr), -1)
    absent = any(item.absent for item in scene.items)
    locations = tuple(loc.id for loc in scene.locations) + ((ABSENT,) if absent else ())
    spot_at = np.full(n, -1, dtype=np.int64)
    play_at = np.zeros(n, dtype=bool)
    use_at = np.zeros(n, dtype=bool)
    for li, loc in enumerate(scene.locations):
        ci = index[(loc.cell.col, loc.cell.row)]
        spot_at[ci] = li
        play_at[ci] = loc.play
        use_at[ci] = loc.use
    capacity = np.array([loc.capacity or 0 for loc in scene.locations] + [0] * absent, dtype=np.int64)
    outside = np.array([region_of.get(c) in outside_regions for c in walkable], dtype=bool)
    sees = np.zeros((n, len(locations)), dtype=bool)
    loc_index = {loc: i for i, loc in enumerate(locations)}
    for vis in scene.visibility:
        seen_from = index.get((vis.cell.col, vis.cell.row))
        if seen_from is not None:
            for loc_id in vis.locations:
                sees[seen_from, loc_index[loc_id]] = True
    walked = location_distances(scene)
    distances = np.array(
        [[walked.get(loc, {}).get(cell, 1 << 30) for cell in walkable] for loc in locations], dtype=np.int64
    ).reshape(len(locations), n)
    carried = carry_locations(scene)  # the one rule engines and evaluators use too
    nearest = np.array(
        [locations.index(carried[cell]) if cell in carried else 0 for cell in walkable], dtype=np.int64
    )
    items = tuple(item.id for item in scene.items)
    sight = CarrierSight(scene)
    open_ids = sorted(set().union(*sight.open.values()))
    return WorldModel(
        cells=np.array(walkable, dtype=np.int64),
        neighbour=neighbour,
        outside=outside,
        spot_at=spot_at,
        play_at=play_at,
        nearest=nearest,
        sees=sees,
        locations=locations,
        items=items,
        cell_index=index,
        distance=distances,
        use_at=use_at,
        capacity=capacity,
        carrier_spot=np.array(
            [locations.index(sight.spot[c]) if c in sight.spot else -1 for c in walkable], dtype=np.int64
        ),
        open_areas=np.array([[r in sight.open[c] for r in open_ids] for c in walkable], bool).reshape(n, -1),
        portable=np.array([item.portable for item in scene.items], dtype=bool),
    )
