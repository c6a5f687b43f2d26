"""Desires as utilities over goals, and what is read off a posterior over them.

A person's goals are the ``K`` items (playing with each) and ``out`` (leaving): ``D = K + 1``
goals. A desire is a utility vector ``u`` over them; the planner solves one MDP per vector
(``brain.model.planner.rewards``), and the robot's posterior is over ``U`` candidate vectors:

- ``favourite`` (the paper's model): ``U = D`` vectors, one per favourite goal ``d``: the
  favourite item is worth ``preferred_utility``, every other item ``other_utility``;
  leaving is worth ``leave_utility_out`` to someone who wants to leave and
  ``leave_utility_item`` to everyone else;
- ``graded``: the grid of every vector whose goals each take one of ``desire_levels``
  utilities evenly spaced from the goal's low value (``other_utility`` for an item,
  ``leave_utility_item`` for ``out``) to its high one (``preferred_utility``,
  ``leave_utility_out``), all-low excluded: ``U = desire_levels**D - 1`` (in a scene with
  no outside, ``out`` is not graded: ``desire_levels**K - 1``). So "likes the
  ball, then the skate, does not care to leave" is one of them.

From weights over the ``U`` vectors: P(each goal is the most wanted) (ties split evenly),
the expected utility of each goal, P(goal ``a`` preferred to goal ``b``) (ties count half)
and the most probable ranking; and the expected utility on a study's rating scale
(:func:`on_scale`: what people are asked, "how much does she want each?"). Pure numpy.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from ..settings import ModelSettings
from .arrays import FloatArray, first_max

DESIRE_MODELS = ("favourite", "graded")


def favourite_utilities(settings: ModelSettings, n_items: int) -> FloatArray:
    """``(D, D)`` row ``d``: the utilities of a person whose favourite goal is ``d``."""
    D = n_items + 1
    u = np.full((D, D), settings.other_utility)
    u[:, n_items] = settings.leave_utility_item
    u[np.arange(n_items), np.arange(n_items)] = settings.preferred_utility
    u[n_items, n_items] = settings.leave_utility_out
    return u


def graded_utilities(settings: ModelSettings, n_items: int, leaves: bool = True) -> FloatArray:
    """``(U, D)`` every vector of the grid (``desire_levels`` values per goal, all-low excluded).

    ``leaves``: whether the scene has an outside to leave to. Without one, ``out`` cannot be
    reached, so vectors that differ in it alone plan alike: ``out`` stays at its low value
    (``leave_utility_item``) and only the items are graded, ``desire_levels**K - 1`` vectors."""
    D, n = n_items + 1, settings.desire_levels
    low = np.array([settings.other_utility] * n_items + [settings.leave_utility_item])
    high = np.array([settings.preferred_utility] * n_items + [settings.leave_utility_out])
    graded = D if leaves else n_items
    steps = np.zeros((n**graded - 1, D))
    steps[:, :graded] = np.array(list(itertools.product(range(n), repeat=graded)), dtype=np.float64)[1:]
    return low + (high - low) * steps / (n - 1)


def utilities(settings: ModelSettings, n_items: int, leaves: bool = True) -> FloatArray:
    """``(U, D)`` the candidate desires of ``settings.desire_model`` (``leaves``: whether the
    scene has an outside; see :func:`graded_utilities`; one favourite keeps ``out``)."""
    if settings.desire_model == "graded":
        return graded_utilities(settings, n_items, leaves)
    return favourite_utilities(settings, n_items)


def goal_scale(settings: ModelSettings, n_items: int) -> tuple[FloatArray, FloatArray]:
    """``(D,)`` each goal's least and ``(D,)`` most utility under the model's desires (either
    desire model): ``other_utility`` to ``preferred_utility`` for an item,
    ``leave_utility_item`` to ``leave_utility_out`` for ``out``."""
    low = np.array([settings.other_utility] * n_items + [settings.leave_utility_item])
    high = np.array([settings.preferred_utility] * n_items + [settings.leave_utility_out])
    return low, high


RATING_SCALE = (1.0, 7.0)
"""The rating scale of Baker, Jara-Ettinger, Saxe and Tenenbaum (2017): 1 (not at all) to 7."""


def on_scale(
    utility: FloatArray, settings: ModelSettings, scale: tuple[float, float] = RATING_SCALE
) -> FloatArray:
    """``(D,)`` expected utilities ``utility`` (``DesireSummary.utility``) on a rating scale:
    each goal's ``[low, high]`` (:func:`goal_scale`) mapped linearly onto ``scale``, so the
    least a goal can be worth reads ``scale[0]`` and the most ``scale[1]``. With one
    favourite it is ``scale[0] + (scale[1] - scale[0]) P(most wanted)``; with graded desires,
    the mean of the goal's level over the grid, rescaled."""
    low, high = goal_scale(settings, len(utility) - 1)
    unit = (utility - low) / np.where(high > low, high - low, 1.0)
    return scale[0] + (scale[1] - scale[0]) * unit


def most_wanted(u: FloatArray) -> FloatArray:
    """``(U, D)`` for each vector, 1 on its most wanted goal (split evenly over ties)."""
    top = np.isclose(u, u.max(axis=1, keepdims=True))
    return top / top.sum(axis=1, keepdims=True)


def preferred(u: FloatArray) -> FloatArray:
    """``(U, D, D)`` 1 where goal ``a`` is worth more than goal ``b`` under the vector, 0.5 on a tie."""
    diff = u[:, :, None] - u[:, None, :]
    return np.where(np.isclose(diff, 0.0), 0.5, (diff > 0).astype(np.float64))


def ranking_text(ranking: tuple[tuple[int, ...], ...], names: Sequence[str]) -> str:
    """A ranking as text: ``ball>skate>out``, tied goals joined by ``=``."""
    return ">".join("=".join(names[d] for d in group) for group in ranking)


def ranking(u: FloatArray) -> tuple[tuple[int, ...], ...]:
    """One vector's goals from most to least wanted, tied goals grouped."""
    order: list[tuple[int, ...]] = []
    for value in sorted(set(np.round(u, 9)), reverse=True):
        order.append(tuple(int(d) for d in np.flatnonzero(np.isclose(u, value))))
    return tuple(order)


@dataclass(frozen=True)
class DesireSummary:
    """What the robot believes a person wants, over ``D`` goals.

    Attributes:
        utility: ``(D,)`` the expected utility of each goal.
        preferred: ``(D, D)`` P(goal ``a`` is worth more than goal ``b``), ties counting half.
        rankings: every ranking some candidate desire has (most wanted first, tied goals
            grouped), shared by the summaries of one model.
        ranking_mass: ``(R,)`` the probability of each.
    """

    utility: FloatArray
    preferred: FloatArray
    rankings: Sequence[tuple[tuple[int, ...], ...]]
    ranking_mass: FloatArray

    @cached_property
    def ranking(self) -> tuple[tuple[int, ...], ...]:
        """The most probable ranking (read once per summary)."""
        return self.rankings[first_max(self.ranking_mass)]

    def probability(self, ranking: tuple[tuple[int, ...], ...]) -> float:
        """The probability of ``ranking`` (0 when no candidate has it)."""
        return float(self.ranking_mass[self.rankings.index(ranking)]) if ranking in self.rankings else 0.0


class Desires:
    """The candidate desires of a model and what is read off weights over them (the tables
    are built once)."""

    def __init__(self, u: FloatArray) -> None:
        self.u = u
        """``(U, D)``."""
        self.wanted = most_wanted(u)
        """``(U, D)``: each vector's most wanted goal (ties split)."""
        self.preferred = preferred(u).reshape(len(u), -1)
        """``(U, D * D)``."""
        keys = [ranking(row) for row in u]
        self.rankings = sorted(set(keys))
        self.rank_of = np.array([self.rankings.index(key) for key in keys], dtype=np.int64)

    def summarise(self, weights: FloatArray) -> DesireSummary:
        """The summary of ``(U,)`` weights."""
        D = self.u.shape[1]
        return DesireSummary(
            utility=weights @ self.u,
            preferred=(weights @ self.preferred).reshape(D, D),
            rankings=self.rankings,
            ranking_mass=np.bincount(self.rank_of, weights=weights, minlength=len(self.rankings)).astype(
                np.float64
            ),
        )
