"""The exact unseen world: every combination of the unseen items' resting places, one branch
each (:class:`~brain.tracking.worldview.WorldView`), every person's chain followed through
every branch and the branches weighed by every person's decisions. The yardstick of the
factored world (:mod:`brain.tracking.itemworld`), and the default where it fits
(:mod:`brain.tracking.unseen`). Both answer the tracker alike: the chains each person keeps
after a look (:meth:`JointWorld.observe`), their truths, their weights. Pure numpy; no I/O.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

import numpy as np

from protocol import Event, State

from ..memory.snapshot import Distribution
from ..model.arrays import FloatArray, IntArray
from ..model.world import WorldModel
from .remembering import robot_items
from .worldview import CARRIED, WorldView

Evidence = Callable[[str], FloatArray]
"""Person -> ``(R,)`` the log-likelihood of their decisions in each of their chains."""


class JointWorld:
    """The joint branches (see the module's note).

    Args:
        view: the robot's hypotheses (rows) of where the items rest.
        people: the people tracked.
        evidence: each person's log-evidence per chain (the tracker's).
    """

    exact = True

    def __init__(self, view: WorldView, people: Sequence[str], evidence: Evidence) -> None:
        self.view = view
        self.model: WorldModel = view.model
        self.people = list(people)
        self.evidence = evidence
        self.branch_truths: list[tuple[int, ...]] = []

    def count(self, person: str) -> int:
        """How many chains ``person`` keeps (one per branch)."""
        return len(self.view.rows)

    def observe(
        self, state: State, robot_cell: int, events: Sequence[Event], holders: dict[str, int | None]
    ) -> dict[str, IntArray]:
        """Take in one tick; person -> the indices of their chains kept (the same for all)."""
        kept = self.view.observe(state, robot_cell, events)
        self.settle(holders)
        return {p: kept for p in self.people}

    def settle(self, holders: dict[str, int | None]) -> None:
        """Read every branch's item values (``holders``: item id -> carrier's cell)."""
        self.branch_truths = [self.view.truth(h, holders) for h in range(len(self.view.rows))]

    def split(self, person: str, cell: int) -> IntArray | None:
        """Branches never split (every combination is one from the start)."""
        return None

    def truths(self, person: str) -> list[tuple[int, ...]]:
        """The item values of each of ``person``'s chains: every branch's."""
        return self.branch_truths

    def branch_weights(self) -> FloatArray:
        """``(H,)`` the posterior of each branch: its prior share times how well it explains
        every person's decisions so far."""
        log_w = self.view.log_prior.copy()
        for person in self.people:
            evidence = self.evidence(person)
            if len(evidence):
                log_w += evidence
        log_w -= log_w.max()
        w = np.exp(log_w)
        return w / w.sum()

    def weights(self, person: str) -> FloatArray:
        """``(H,)`` the weights ``person``'s chains are mixed with (the branches')."""
        return self.branch_weights()

    def likeliest(self, person: str | None = None) -> int:
        """The index of the likeliest chain (of anyone: the likeliest branch)."""
        return int(np.argmax(self.branch_weights()))

    def truth(self) -> tuple[int, ...]:
        """The item values of the likeliest branch."""
        return self.branch_truths[self.likeliest()]

    def believed(self) -> IntArray:
        """``(K,)`` where the robot acts as if each item rests: the likeliest branch's
        location (:data:`~brain.tracking.worldview.CARRIED` when carried)."""
        return self.view.rows[self.likeliest()]

    def where(self) -> FloatArray:
        """``(K, L)`` P(each item rests at each location), over the branches weighted by their
        posterior: a carried item adds nothing, rows normalised where they have mass."""
        model, rows, weights = self.model, self.view.rows, self.branch_weights()
        where = np.zeros((model.n_items, model.n_locations))
        for k in range(model.n_items):
            resting = rows[:, k] != CARRIED
            np.add.at(where[k], rows[resting, k], weights[resting])
        total = where.sum(axis=1, keepdims=True)
        return np.divide(where, total, out=np.zeros_like(where), where=total > 0)

    def items(self) -> dict[str, Distribution]:
        """Item id -> where the robot believes it rests (:func:`.remembering.robot_items`)."""
        return robot_items(self.model, self.truth(), self.branch_truths, self.branch_weights())
