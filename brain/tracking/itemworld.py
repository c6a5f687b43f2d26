"""The factored unseen world: the robot's belief about each unseen item on its own
(:class:`~brain.tracking.itemview.ItemView`), and per person the few rows of it their
percepts told apart (:class:`~brain.tracking.personrows.PersonRows`), each one chain of the
tracker. Memory and time grow with the items (``K L`` per person and row), not with their
product (``L**K`` branches, :mod:`brain.tracking.jointworld`).

The robot's posterior about item ``k``'s origin is

    P(k at l | everything)  ∝  Q_k(l) · prod_persons lambda_p[k, l]

(``Q``: what the robot saw, ``lambda_p``: person ``p``'s decisions' evidence about the item,
:meth:`PersonRows.message`), and person ``p``'s rows are weighed with the others' evidence in
their prior (``Q`` times ``prod_{p' != p} lambda_p'``): belief propagation over the people
and the items, exact for one person and items their rows hold apart. What it loses against
the joint branches: the capacities of locations (origins are independent a priori); the
coupling of items through the people (a product of per-item messages stands for the joint
likelihood); the rows beyond ``cap`` a person's percepts would tell apart; and in a row whose
item's origin is a set, its filter reads that item's truth at the set's likeliest origin
(the graded prior of a person first seen, and false beliefs, read it). Pure numpy; no I/O.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from protocol import Event, State

from ..memory.snapshot import Distribution
from ..model.arrays import FloatArray, IntArray
from ..model.world import WorldModel, location_of
from .itemview import CARRIED, UNKNOWN, ItemView
from .jointworld import Evidence
from .personrows import PersonRows


class ItemWorld:
    """The factored world (see the module's note).

    Args:
        view: the robot's per-item belief.
        people: the people tracked.
        evidence: each person's log-evidence per chain (the tracker's).
        cap: the most rows a person keeps.
    """

    exact = False

    def __init__(self, view: ItemView, people: Sequence[str], evidence: Evidence, cap: int) -> None:
        self.view = view
        self.model: WorldModel = view.model
        self.evidence = evidence
        self.rows = {p: PersonRows(view.origin > 0, cap) for p in people}
        self.holders: dict[str, int | None] = {}
        self._truths: dict[str, list[tuple[int, ...]]] = {}
        self._looks = 0
        """Bumped whenever the robot's view or a person's rows change (the messages' and the
        weights' key)."""
        self._messages_kept: dict[str, tuple[tuple[object, ...], FloatArray]] = {}
        self._weights_kept: dict[str, tuple[tuple[object, ...], FloatArray]] = {}

    def count(self, person: str) -> int:
        """How many chains ``person`` keeps (one per row)."""
        return len(self.rows[person])

    def observe(
        self, state: State, robot_cell: int, events: Sequence[Event], holders: dict[str, int | None]
    ) -> dict[str, IntArray]:
        """Take in one tick; person -> the indices of their chains kept."""
        origin, sets = self.view.origin.copy(), {p: rows.sets for p, rows in self.rows.items()}
        self.view.observe(state, robot_cell, events)
        kept = {p: rows.restrict(self.view.origin) for p, rows in self.rows.items()}
        if not np.array_equal(origin, self.view.origin) or any(
            not np.array_equal(sets[p], rows.sets) for p, rows in self.rows.items()
        ):
            self._looks += 1
        self.settle(holders)
        return kept

    def settle(self, holders: dict[str, int | None]) -> None:
        """Read every row's item values (``holders``: item id -> carrier's cell)."""
        self.holders = holders
        self._truths = {p: self._row_truths(rows) for p, rows in self.rows.items()}

    def _row_truths(self, rows: PersonRows) -> list[tuple[int, ...]]:
        """Each row's item values: its set's likeliest origin under what the robot saw."""
        origins = np.argmax(rows.sets * self.view.origin[None], axis=2)  # (R, K)
        return self.view.values_of_rows(origins, self.holders)

    def split(self, person: str, cell: int) -> IntArray | None:
        """Split ``person``'s rows on what ``cell`` sees (:meth:`PersonRows.split`); the
        source row of each row now, or ``None`` when nothing split."""
        rows = self.rows[person]
        unknown = self.view.known == UNKNOWN
        if not unknown.any():
            return None
        seen = self.model.sees[cell]
        if not (rows.sets[:, unknown] & (seen & (self.view.origin > 0))[unknown][None]).any():
            return None  # no row holds a spot in view that the robot gives mass: nothing splits
        before, sets = len(rows), rows.sets
        source = rows.split(self.model.sees[cell], self.cavity(person), unknown, self.evidence(person))
        if not np.array_equal(sets, rows.sets):
            self._looks += 1
        if len(source) == before and bool((source == np.arange(before)).all()):
            return None
        self._truths[person] = self._row_truths(rows)
        return source

    def truths(self, person: str) -> list[tuple[int, ...]]:
        """The item values of each of ``person``'s chains."""
        return self._truths[person]

    def _messages(self, evidence: dict[str, FloatArray] | None = None) -> dict[str, FloatArray]:
        """Person -> ``(K, L)`` their evidence about each item (:meth:`PersonRows.message`;
        none from one row), kept until their evidence (``evidence``: person -> ``(R,)``, read
        here when not given) or rows or the robot's view change."""
        out = {}
        for p, rows in self.rows.items():
            if len(rows) < 2:
                continue
            mine = self.evidence(p) if evidence is None else evidence[p]
            key = (self._looks, mine.tobytes())
            kept = self._messages_kept.get(p)
            if kept is None or kept[0] != key:
                kept = (key, rows.message(self.view.origin, mine))
                self._messages_kept[p] = kept
            out[p] = kept[1]
        return out

    def cavity(self, person: str, messages: dict[str, FloatArray] | None = None) -> FloatArray:
        """``(K, L)`` the robot's belief with every person's evidence but ``person``'s."""
        messages = self._messages() if messages is None else messages
        q = self.view.origin.copy()
        for p, lam in messages.items():
            if p != person:
                q *= lam
        return _normalised(q)

    def posterior(self) -> FloatArray:
        """``(K, L)`` P(each item's origin) given what the robot saw and everyone's decisions."""
        return self.cavity("", self._messages())

    def weights(self, person: str) -> FloatArray:
        """``(R,)`` the weights ``person``'s chains are mixed with, kept until anyone's
        evidence or rows or the robot's view change (read many times a tick, by every
        person's online estimate)."""
        evidence = {p: self.evidence(p) for p in self.rows}
        key = (self._looks, b"|".join(e.tobytes() for e in evidence.values()))
        kept = self._weights_kept.get(person)
        if kept is None or kept[0] != key:
            cavity = self.cavity(person, self._messages(evidence))
            kept = (key, self.rows[person].weights(cavity, evidence[person]))
            self._weights_kept[person] = kept
        return kept[1]

    def likeliest(self, person: str | None = None) -> int:
        """The index of ``person``'s likeliest chain."""
        return 0 if person is None else int(np.argmax(self.weights(person)))

    def truth(self) -> tuple[int, ...]:
        """The item values of the likeliest origins (item by item)."""
        return self.view.values(np.argmax(self.posterior(), axis=1), self.holders)

    def believed(self) -> IntArray:
        """``(K,)`` where the robot acts as if each item rests: known, or its likeliest
        origin; :data:`~brain.tracking.itemview.CARRIED` when carried."""
        view = self.view
        return np.where(view.known == UNKNOWN, np.argmax(self.posterior(), axis=1), view.known)

    def where(self) -> FloatArray:
        """``(K, L)`` P(each item rests at each location): a carried item's row sums to 0."""
        return self.view.resting(self.posterior())

    def items(self) -> dict[str, Distribution]:
        """Item id -> where the robot believes it rests (location id -> probability); a
        carried item counts where its carrier's location is."""
        model, where, truth = self.model, self.where(), self.truth()
        out: dict[str, Distribution] = {}
        for k, item in enumerate(model.items):
            if self.view.known[k] == CARRIED:
                out[item] = {model.locations[location_of(truth[k])]: 1.0}
            else:
                out[item] = {model.locations[int(i)]: float(where[k, i]) for i in np.flatnonzero(where[k])}
        return out


def _normalised(q: FloatArray) -> FloatArray:
    total = q.sum(axis=1, keepdims=True)
    return np.divide(q, total, out=np.zeros_like(q), where=total > 0)
