"""What a person model starts a day from when the brain remembers the person from an earlier
one (:mod:`brain.memory`): pure numpy, no I/O.

A person's belief in the morning is what the brain read them to believe at night: per item,
the remembered marginal ``m`` over locations weighs each point ``p`` of the grid of initial
beliefs (:mod:`brain.model.graded`) by ``prod_l (p_l + FLOOR)^(strength m_l)`` (as if the
person had looked ``strength`` times and found the item as ``m`` says), times the point's own
prior weight, then mixed back with those own weights by ``forget`` (what a night may blur).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..arrays import FloatArray, IntArray

FLOOR = 0.05
"""Added to every point's probability of a place before it is weighed: a place the person
was read to believe in the least is not ruled out of their morning belief."""


@dataclass(frozen=True)
class Remembered:
    """A person as remembered from an earlier day.

    Attributes:
        desires: ``(U,)`` the prior over the model's candidate desires (``None``: even).
        beliefs: per item, the remembered ``(L,)`` belief over locations (``None``: not
            remembered: the grid's own prior for it).
    """

    desires: FloatArray | None
    beliefs: tuple[FloatArray | None, ...]


def point_weights(
    points: FloatArray, base: FloatArray, remembered: FloatArray, strength: float, forget: float
) -> FloatArray:
    """``(P,)`` the morning weights of one item's grid points ``(P, L)`` (``base``: their own
    ``(P,)`` weights) for a person remembered to believe the item is at each location with
    ``remembered`` ``(L,)``."""
    log_w = np.log(np.maximum(base, 1e-300)) + strength * (np.log(points + FLOOR) @ remembered)
    w = np.exp(log_w - log_w.max()) * (base > 0)
    w /= w.sum()
    own = base / base.sum()
    return (1.0 - forget) * w + forget * own


def hypothesis_weights(
    combos: IntArray,
    points: FloatArray,
    bases: Sequence[FloatArray],
    remembered: Sequence[FloatArray | None],
    strength: float,
    forget: float,
) -> FloatArray:
    """``(G,)`` the morning weights of the hypotheses ``combos`` ``(G, K)`` (each item's point):
    per item :func:`point_weights` (``bases[k]``: the item's own point weights) where the item
    is remembered, its own weights where not, multiplied."""
    weights = np.ones(len(combos))
    for k, (base, marginal) in enumerate(zip(bases, remembered, strict=True)):
        per_point = base if marginal is None else point_weights(points, base, marginal, strength, forget)
        weights *= per_point[combos[:, k]]
    return weights / weights.sum()
