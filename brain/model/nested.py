"""Nested beliefs: where person A believes person B believes each item is (pure numpy).

A's model of B is B's belief filter (the paper's update, :mod:`brain.model.belief`, item by
item) run on the percepts A can attribute to B: while A sees B, B's belief follows what B
sees; while A does not, it stays put, except that A may think B came back and looked unseen:
at a rate ``peek`` per second, A's model of B moves toward what A believes
(:class:`NestedBeliefs`). This is what separates it from the robot's own estimate of B, which
follows every percept of B's that the robot sees.

Who sees whom: a person sees another exactly where they would see an item the other carries
(:meth:`~brain.model.world.WorldModel.sees_carrier`, the scene's visibility by
``protocol.carry.CarrierSight``).

The paper's update is a product over items (the percept's likelihood and the change weights
both are), so one item's update is exact for a belief that is a product over items, which
this keeps: ``(P, K, V)`` for the ``P`` ordered pairs of people, per item a distribution over
its values (``2 l`` resting at location ``l``, ``2 l + 1`` carried near it).

The backward pass (:func:`smoothed_nested`): in this model nothing A sees later is evidence
about A's model of B (while A does not see B, A learns nothing of what B saw), so what a whole
run adds is what the robot learns later of the beliefs the filter leans on: B's own belief
where every pair starts, and A's own belief, toward which A's model of an unseen B drifts.
The smoothed nested beliefs are the same filter run again over the same percepts with the
robot's smoothed estimates of those first-order beliefs in place of its online ones.
"""

from __future__ import annotations

import functools
import itertools
from collections.abc import Callable, Mapping, Sequence

import numpy as np

from .arrays import FloatArray
from .belief import UNNOTICED, Percept, changes
from .world import RESTING, VALUES_PER_LOCATION, WorldModel, location_of


def item_transitions(model: WorldModel, p: Percept, r: float, delta: float) -> FloatArray:
    """``(K, V, V)``: per item, ``T[i, j] = P(value i now | value j before, percept p)`` of
    the paper's update (``r`` for a change the person can see, ``delta`` for a percept the
    value does not reproduce); columns sum to one."""
    V = model.n_values
    values = np.arange(V)
    seen = np.array(p.seen)[:, None]  # (K, 1)
    visible = model.sees[p.cell][location_of(values)][None, :]  # (1, V): the value's place is in view
    match = np.where(seen >= 0, values[None, :] == seen, (seen == UNNOTICED) | ~visible)  # (K, V)
    likelihood = np.where(match, 1.0 - delta, delta)
    ch = changes(model, p)
    same = np.eye(V, dtype=bool)[None]
    change = np.where(ch.allowed() & ~same, r, 0.0) + same  # by the old value j
    if ch.lost:  # what was carried off is redrawn first
        change = change @ ch.redraw()
    t = likelihood[:, :, None] * change  # (K, V_i, V_j)
    return t / t.sum(axis=1, keepdims=True)


class NestedBeliefs:
    """For each ordered pair ``(A, B)`` of ``people``, the robot's estimate of A's belief about
    B's belief: ``(K, V)`` per pair. Feed it one tick at a time (:meth:`observe`).

    Args:
        model: the scene's world model.
        people: the person ids, in the order the pairs are built from.
        r, delta: the belief update's factors (``ModelSettings``).
        peek: the rate (per second) at which A thinks B may have come back and looked unseen,
            moving A's model of B toward A's own belief (0: never).
    """

    def __init__(
        self, model: WorldModel, people: Sequence[str], r: float, delta: float, peek: float = 0.0
    ) -> None:
        self.model, self.r, self.delta, self.peek = model, r, delta, peek
        self.people = list(people)
        self.pairs = list(itertools.permutations(self.people, 2))
        self.values: FloatArray | None = None
        """``(P, K, V)``; ``None`` until the first tick."""
        self.time: float | None = None
        self.inputs: list[tuple[float, dict[str, int], dict[str, Percept]]] = []
        """Every tick's ``(time, cells, percepts)``, in order, for :func:`smoothed_nested`."""
        self._transitions: dict[Percept, FloatArray] = {}
        self._seen: dict[tuple[int, int], bool] = {}
        """(viewer cell, other cell) -> :meth:`sees` (the map's sight never changes)."""

    def observe(
        self,
        time: float,
        cells: Mapping[str, int],
        percepts: Mapping[str, Percept],
        belief_of: Callable[[str], FloatArray | None],
    ) -> None:
        """One tick at engine time ``time`` (s): each person's cell index and percept (people
        the robot cannot place are missing), and ``belief_of(person)``, the robot's estimate of
        that person's own belief, ``(K, L)`` (read only when needed). At the first tick every
        pair starts from B's own estimated belief (uniform when there is none)."""
        self.inputs.append((time, dict(cells), dict(percepts)))
        if self.values is None:
            uniform = np.full((self.model.n_items, self.model.n_locations), 1.0 / self.model.n_locations)
            starts = {
                p: self._resting(own if (own := belief_of(p)) is not None else uniform) for p in self.people
            }
            shape = (0, self.model.n_items, self.model.n_values)
            self.values = (
                np.stack([starts[other] for _, other in self.pairs]) if self.pairs else np.zeros(shape)
            )
            self.time = time
            return
        elapsed = 0.0 if self.time is None else max(time - self.time, 0.0)
        self.time = time
        transitions = {b: self._transition(p) for b, p in percepts.items()}
        blend = 1.0 - np.exp(-self.peek * elapsed)
        seen: dict[str, list[int]] = {}  # B -> the pairs whose A sees B
        unseen: list[int] = []
        for n, (a, b) in enumerate(self.pairs):
            if self.sees(cells.get(a), cells.get(b)) and b in transitions:
                seen.setdefault(b, []).append(n)
            elif blend > 0.0:
                unseen.append(n)
        for b, pairs in seen.items():  # B's percept moves every A's model of B at once
            self.values[pairs] = np.einsum("kij,nkj->nki", transitions[b], self.values[pairs])
        if unseen:
            self._drift(unseen, blend, belief_of)

    def _drift(
        self, pairs: Sequence[int], blend: float, belief_of: Callable[[str], FloatArray | None]
    ) -> None:
        """Move each of ``pairs``' (indices of ``self.pairs``: A does not see B) model of B
        the share ``blend`` toward A's own belief (``belief_of``, read once a person; a pair
        whose A has none keeps it)."""
        assert self.values is not None
        own: dict[str, FloatArray | None] = {}
        moved, toward = [], []
        for n in pairs:
            a = self.pairs[n][0]
            if a not in own:
                belief = belief_of(a)
                own[a] = None if belief is None else self._resting(belief)
            if (resting := own[a]) is not None:
                moved.append(n)
                toward.append(resting)
        if moved:
            self.values[moved] = (1.0 - blend) * self.values[moved] + blend * np.stack(toward)

    def _transition(self, p: Percept) -> FloatArray:
        """:func:`item_transitions` of ``p``, remembered (a percept repeats tick after tick)."""
        found = self._transitions.get(p)
        if found is None:
            if len(self._transitions) >= 4096:
                self._transitions.clear()
            found = self._transitions[p] = item_transitions(self.model, p, self.r, self.delta)
        return found

    def sees(self, viewer: int | None, other: int | None) -> bool:
        """Whether a person on cell index ``viewer`` sees one on ``other``."""
        if viewer is None or other is None:
            return False
        found = self._seen.get((viewer, other))
        if found is None:
            found = self._seen[(viewer, other)] = bool(self.model.sees_carrier(viewer, np.array(other)))
        return found

    def locations(self, a: str, b: str) -> FloatArray:
        """``(K, L)`` where A believes B believes each item is (carried counts near its place)."""
        return self.all_locations()[self.pairs.index((a, b))]

    def all_locations(self) -> FloatArray:
        """``(P, K, L)``: :meth:`locations` of every pair, in the order of ``pairs``."""
        if self.values is None:
            raise ValueError("no tick observed yet")
        model = self.model
        shape = (len(self.pairs), model.n_items, model.n_locations, VALUES_PER_LOCATION)
        return self.values.reshape(shape).sum(axis=3)

    def _resting(self, beliefs: FloatArray) -> FloatArray:
        """``(K, V)``: a ``(K, L)`` belief over locations as values, each at rest there."""
        out = np.zeros((self.model.n_items, self.model.n_values))
        out[:, RESTING] = beliefs
        return out


def smoothed_nested(
    nested: NestedBeliefs, belief_at: Callable[[int, str], FloatArray | None]
) -> list[FloatArray]:
    """The backward pass of ``nested`` (see the module docstring): its filter run again over
    the ticks it saw (:attr:`NestedBeliefs.inputs`), with ``belief_at(n, person)`` (the
    robot's smoothed estimate of ``person``'s own ``(K, L)`` belief at the ``n``-th of those
    ticks, ``None`` before one exists) in place of the online estimates; ``(P, K, L)`` per tick."""
    again = NestedBeliefs(nested.model, nested.people, nested.r, nested.delta, nested.peek)
    out = []
    for n, (time, cells, percepts) in enumerate(nested.inputs):
        again.observe(time, cells, percepts, functools.partial(belief_at, n))
        out.append(again.all_locations())
    again.inputs.clear()
    return out
