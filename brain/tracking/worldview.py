"""What an embodied robot knows of where the items rest (``ModelSettings.perception =
"embodied"``).

The robot sees the item spots the visibility table lists from its own cell, and it tracks
every person and what they hold and do (the house's sensors, or its own ears): so an item's
resting place is known when the robot sees it, when someone puts it down, and when someone
takes it (it was where they took it from); an item resting out of view and never seen is
not. The view keeps ``H`` hypotheses ``(H, K)`` of every item's resting location (``-1`` while
carried): every combination the scene allows, at first, cut down by what the robot sees.
Rows are never merged, because each is a branch the tracker follows every person's mind
through (:class:`~brain.tracking.tracker.MindTracker`): the person's percepts differ between
branches, so their action likelihoods weigh the branches (joint inference of the people's
minds and the unseen world). Pure numpy; no I/O.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from protocol import Event, EventKind, State

from ..model.arrays import IntArray
from ..model.world import ABSENT, WorldModel, is_resting, location_of, value_of

CARRIED = -1


class WorldView:
    """The robot's hypotheses about where the items rest.

    Args:
        model: the world model (locations, what each cell sees, capacities).
        absent: indices of the items the scene says are absent (never in view, at
            :data:`~brain.model.world.ABSENT`).
    """

    def __init__(self, model: WorldModel, absent: Sequence[int] = ()) -> None:
        self.model = model
        resting = location_of(model.worlds[is_resting(model.worlds).all(axis=1) & model.allowed])  # (H, K)
        for k in absent:
            resting = resting[resting[:, k] == model.locations.index(ABSENT)]
        self.rows: IntArray = resting.astype(np.int64)
        self.log_prior = np.full(len(self.rows), -np.log(max(len(self.rows), 1)))

    def observe(self, state: State, robot_cell: int, events: Sequence[Event]) -> IntArray:
        """Take in one tick; return the indices of the rows kept (in order), the others
        ruled out by what the robot saw."""
        model = self.model
        rows = self.rows.copy()
        keep = np.ones(len(rows), dtype=bool)
        for event in events:
            if event.item not in model.items or event.location not in model.locations:
                continue
            k, loc = model.items.index(event.item), model.locations.index(event.location)
            if event.kind is EventKind.TAKE:
                keep &= (rows[:, k] == loc) | (rows[:, k] == CARRIED)
        visible = model.sees[robot_cell]
        for item in state.items:
            if item.id not in model.items:
                continue
            k = model.items.index(item.id)
            if item.held_by is not None:
                rows[:, k] = CARRIED
            elif item.location in model.locations and (
                visible[model.locations.index(item.location)] or bool((rows[:, k] == CARRIED).all())
            ):  # seen, or just put down by someone the robot tracks
                loc = model.locations.index(item.location)
                keep &= (rows[:, k] == loc) | (rows[:, k] == CARRIED)
                rows[:, k] = loc
            else:  # resting out of view: not at any spot the robot sees
                keep &= (rows[:, k] == CARRIED) | ~visible[np.maximum(rows[:, k], 0)]
        if not keep.any():  # nothing fits (an engine that moved an item unseen): start over from here
            keep[:] = True
        self.rows, self.log_prior = rows[keep], self.log_prior[keep]
        return np.flatnonzero(keep)

    def truth(self, row: int, holders: dict[str, int | None]) -> tuple[int, ...]:
        """The item values of branch ``row``: ``2 l`` resting at ``l``, ``2 l + 1`` carried by
        someone whose cell's nearest location is ``l`` (``holders``: item id -> carrier's cell)."""
        values = []
        for k, item in enumerate(self.model.items):
            cell = holders.get(item)
            if cell is not None:
                values.append(value_of(int(self.model.nearest[cell]), held=True))
            else:
                values.append(value_of(int(max(self.rows[row, k], 0))))
        return tuple(values)
