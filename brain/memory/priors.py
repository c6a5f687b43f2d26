"""A day's priors from the memory of the days before it: pure numpy, no I/O.

- **Desires.** P(each goal is the most wanted) at the end of the last day, with the drift the
  model assumes (``memory_drift``: the chance per day that a person's favourites are redrawn),
  becomes the prior over the candidate desires (:func:`desire_prior`).
- **A person's belief in the morning** is what the brain read them to believe at night
  (:func:`remembered_beliefs`, weighed by :mod:`brain.model.person.remembered`).
- **The robot's own knowledge** of where each item rests weighs the embodied robot's
  hypotheses of the unseen world the same way (:func:`view_log_prior`).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..model.arrays import FloatArray, IntArray
from ..model.desires import most_wanted
from ..model.person.remembered import Remembered
from .snapshot import Distribution


def _vector(distribution: Distribution, ids: Sequence[str]) -> FloatArray | None:
    """``distribution`` over ``ids`` (normalised), or ``None`` when it gives them nothing."""
    v = np.array([max(float(distribution.get(i, 0.0)), 0.0) for i in ids])
    total = v.sum()
    return v / total if total > 0 else None


def desire_prior(
    preference: Distribution, goals: Sequence[str], utilities: FloatArray, drift: float
) -> FloatArray | None:
    """``(U,)`` the prior over the candidate desires ``utilities`` (``(U, D)``, goals in the
    order of ``goals``) of a person remembered to want each goal most with ``preference``: each
    goal's probability shared evenly by the candidates under which it is the most wanted, then
    ``drift`` of it spread evenly over every candidate. ``None`` when the memory names none
    of ``goals``."""
    top = _vector(preference, goals)
    if top is None:
        return None
    wanted = most_wanted(utilities)  # (U, D)
    share = wanted / np.maximum(wanted.sum(axis=0, keepdims=True), 1e-300)
    prior = share @ top
    prior = prior / prior.sum()
    return (1.0 - drift) * prior + drift / len(prior)


def remembered_beliefs(
    beliefs: dict[str, Distribution], items: Sequence[str], locations: Sequence[str]
) -> list[FloatArray | None]:
    """Per item of ``items``, the remembered ``(L,)`` belief over ``locations`` (``None``: not
    remembered, or it names none of them)."""
    return [_vector(beliefs[item], locations) if item in beliefs else None for item in items]


def view_log_prior(
    rows: IntArray,
    items: Sequence[str],
    locations: Sequence[str],
    known: dict[str, Distribution],
    forget: float,
) -> FloatArray:
    """``(H,)`` log prior of the embodied robot's hypotheses ``rows`` ``(H, K)`` (each item's
    resting location) given where it remembers each item rests, ``forget`` of it spread evenly
    (something may have moved overnight); items it does not remember are even."""
    log_p = np.zeros(len(rows))
    for k, item in enumerate(items):
        marginal = _vector(known.get(item, {}), locations)
        if marginal is None:
            continue
        p = (1.0 - forget) * marginal + forget / len(locations)
        log_p += np.log(p[np.maximum(rows[:, k], 0)])
    return log_p - np.logaddexp.reduce(log_p) if len(log_p) else log_p


def remembered(
    preference: Distribution,
    beliefs: dict[str, Distribution],
    goals: Sequence[str],
    utilities: FloatArray,
    items: Sequence[str],
    locations: Sequence[str],
    drift: float,
) -> Remembered:
    """A remembered person as their model's prior reads them (:class:`Remembered`)."""
    return Remembered(
        desire_prior(preference, goals, utilities, drift),
        tuple(remembered_beliefs(beliefs, items, locations)),
    )
