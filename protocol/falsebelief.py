"""The false-belief rule: when a belief about where an item is counts as false, not as
ignorance. One rule, used by the brain (its ``false_belief`` estimates) and by the evaluation
that scores them against the people's true beliefs.

A belief is false when it gives the item's true location less than :data:`FALSE_BELIEF_MASS`
times what it gives its likeliest location. A belief spread evenly over places that include
the truth is ignorance, not a false belief, however many places (a fixed threshold, ``< mass``,
would call ignorance over more than ``1 / mass`` places false).
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any, Protocol, overload

FALSE_BELIEF_MASS = 0.1
"""The share of the likeliest location's probability below which the true location's makes a
belief false (the brain's default ``false_belief_mass``; the evaluation scores with it)."""


class Probabilities(Protocol):
    """An array of probabilities (a numpy array, say), over which the rule broadcasts."""

    def __lt__(self, other: Any, /) -> Any: ...

    def __rmul__(self, other: float, /) -> Any: ...


@overload
def is_false_belief(at_truth: float, likeliest: float, mass: float = FALSE_BELIEF_MASS) -> bool: ...


@overload
def is_false_belief(
    at_truth: Probabilities, likeliest: Probabilities, mass: float = FALSE_BELIEF_MASS
) -> Any: ...


def is_false_belief(at_truth: Any, likeliest: Any, mass: float = FALSE_BELIEF_MASS) -> Any:
    """Whether a belief giving an item's true location probability ``at_truth`` and its
    likeliest location ``likeliest`` is false: ``at_truth < mass * likeliest`` (element-wise
    for arrays of probabilities; ``mass`` in ``(0, 1]``)."""
    return at_truth < mass * likeliest


def believes_falsely(belief: Mapping[str, float], location: str, mass: float = FALSE_BELIEF_MASS) -> bool:
    """Whether ``belief`` (location id -> probability; a missing one is 0) about an item now at
    ``location`` is false (:func:`is_false_belief`; an empty belief is no belief, not a false one)."""
    return bool(is_false_belief(belief.get(location, 0.0), max(belief.values(), default=0.0), mass))
