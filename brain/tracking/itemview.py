"""What an embodied robot knows of where the items rest, one item at a time (the factored
unseen world, ``ModelSettings.unseen_world``).

:class:`~brain.tracking.worldview.WorldView` keeps every combination of the unseen items'
resting places (``L**K`` rows); this view keeps, per item, one distribution over the
locations it rested at when the episode began (its *origin*): ``origin`` ``(K, L)``, each
row summing to one, the product of the rows the robot's prior over whole worlds. It is
updated by what the robot sees, as the rows of the joint view are:

- a sighting of the item resting at a spot the robot sees, or a put-down by someone it
  tracks, collapses its origin to that spot (while its origin was unknown) and makes its
  place known;
- a take fixes its origin to the spot it was taken from (the taker was seen there);
- a spot the robot sees without the item removes that spot's mass (renormalised).

``known`` ``(K,)`` says where each item is now: a location index, :data:`CARRIED` (held by
someone the robot tracks), or :data:`UNKNOWN` (resting where the robot has not seen it:
then it is still at its origin). Locations' capacities are not kept (the items' origins
are independent): the one loss of this view against the joint one before the people's
evidence. Pure numpy; no I/O.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from protocol import Event, EventKind, State

from ..model.arrays import FloatArray, IntArray
from ..model.world import ABSENT, WorldModel, value_of

CARRIED = -1
"""``known``: held by someone the robot tracks."""
UNKNOWN = -2
"""``known``: resting where the robot has not seen it (still at its origin)."""


class ItemView:
    """The robot's per-item belief about where the unseen items rest.

    Args:
        model: the world model (locations, what each cell sees).
        absent: indices of the items the scene says are absent (at
            :data:`~brain.model.world.ABSENT`, known).
    """

    def __init__(self, model: WorldModel, absent: Sequence[int] = ()) -> None:
        self.model = model
        K, L = model.n_items, model.n_locations
        self.prior = np.full((K, L), 1.0 / max(L, 1))
        """``(K, L)`` the origin before anything is seen: every location alike (the joint
        view's marginal without capacities; an item not absent may rest at ``absent``)."""
        self.known: IntArray = np.full(K, UNKNOWN, dtype=np.int64)
        for k in absent:
            self.prior[k] = 0.0
            self.prior[k, model.locations.index(ABSENT)] = 1.0
            self.known[k] = model.locations.index(ABSENT)
        self.origin: FloatArray = self.prior.copy()

    def observe(self, state: State, robot_cell: int, events: Sequence[Event]) -> None:
        """Take in one tick: what the robot sees from ``robot_cell``, and the takes and
        put-downs of the people it tracks (``state``: the engine's, ``events``: the tick's)."""
        model = self.model
        for event in events:
            if event.kind is not EventKind.TAKE:
                continue
            if event.item in model.items and event.location in model.locations:
                k = model.items.index(event.item)
                if self.known[k] == UNKNOWN:
                    self._collapse(k, model.locations.index(event.location))
        visible = model.sees[robot_cell]
        for item in state.items:
            if item.id not in model.items:
                continue
            k = model.items.index(item.id)
            if item.held_by is not None:
                self.known[k] = CARRIED
            elif item.location in model.locations and (
                visible[model.locations.index(item.location)] or self.known[k] == CARRIED
            ):  # seen, or just put down by someone the robot tracks
                loc = model.locations.index(item.location)
                if self.known[k] == UNKNOWN:
                    self._collapse(k, loc)
                self.known[k] = loc
            elif self.known[k] == UNKNOWN:  # resting out of view: at no spot the robot sees
                self._exclude(k, visible)

    def _collapse(self, k: int, loc: int) -> None:
        """Item ``k``'s origin is ``loc`` (one that gave it nothing, an engine that moved it
        unseen, is believed all the same)."""
        self.origin[k] = 0.0
        self.origin[k, loc] = 1.0

    def _exclude(self, k: int, seen: IntArray) -> None:
        """Item ``k`` is at none of the spots ``seen`` ``(L,)`` (bool) shows: their mass goes
        (when nothing is left, start over from the prior off those spots)."""
        left = np.where(seen, 0.0, self.origin[k])
        if left.sum() <= 0:
            left = np.where(seen, 0.0, self.prior[k])
        if left.sum() > 0:
            self.origin[k] = left / left.sum()

    def values(self, origins: IntArray, holders: dict[str, int | None]) -> tuple[int, ...]:
        """The item values of a world whose unseen items rest at ``origins`` ``(K,)``
        (location indices; read where ``known`` is :data:`UNKNOWN`): ``2 l`` resting at ``l``,
        ``2 l + 1`` carried by someone whose cell's nearest location is ``l`` (``holders``:
        item id -> carrier's cell)."""
        out = []
        for k, item in enumerate(self.model.items):
            cell = holders.get(item)
            if cell is not None:
                out.append(value_of(int(self.model.nearest[cell]), held=True))
            elif self.known[k] >= 0:
                out.append(value_of(int(self.known[k])))
            else:
                out.append(value_of(int(origins[k])))
        return tuple(out)

    def values_of_rows(self, origins: IntArray, holders: dict[str, int | None]) -> list[tuple[int, ...]]:
        """:meth:`values` of ``R`` worlds at once, ``origins`` ``(R, K)``."""
        fixed = np.array(self.values(np.zeros(len(self.known), dtype=np.int64), holders), dtype=np.int64)
        carried = np.array([holders.get(item) is not None for item in self.model.items], dtype=bool)
        unseen = (self.known < 0) & ~carried  # (K,) read at each world's origin
        out = np.where(unseen[None, :], value_of(origins.astype(np.int64)), fixed[None, :])
        return [tuple(row) for row in out.tolist()]

    def resting(self, posterior: FloatArray) -> FloatArray:
        """``(K, L)`` P(each item rests at each location) now, given ``posterior`` ``(K, L)``
        over the unseen items' origins: a known item at its place, a carried one nowhere."""
        out = np.where((self.known == UNKNOWN)[:, None], posterior, 0.0)
        placed = np.flatnonzero(self.known >= 0)
        out[placed, self.known[placed]] = 1.0
        return out
