"""The brain's value of each rated quantity (``toyroom fit --judgments``), read off the
online or the smoothed estimate of the person at the judgment's tick.

How each quantity is read (``K`` items, goals ``D = K + 1``: the items, then ``out``):

- ``belief``: P(the person believes item ``k`` is at location ``l``), ``Estimate.beliefs``;
- ``desire``: P(goal ``d`` is the most wanted), ``Estimate.preference`` (ties split);
- ``utility``: the posterior mean of the goal's utility on the goal's own scale,
  ``(E[u_d] - low_d) / (high_d - low_d)`` in ``[0, 1]``, where ``low`` and ``high`` are the
  goal's least and most utility under the model (``other_utility`` and
  ``preferred_utility`` for an item, ``leave_utility_item`` and ``leave_utility_out`` for
  ``out``): so an item and ``out`` rated on one scale are compared on one. Graded desires:
  the mean of the goal's level over the grid, divided by ``desire_levels - 1``. One
  favourite: every candidate gives a goal ``high`` when it is the favourite and ``low``
  otherwise, so the utility is exactly P(most wanted), ``desire``;
- ``rank``: the goal's expected rank among the goals, ``1 + sum_{b != d} P(u_b > u_d)`` (ties
  counting half; 1 the most wanted), from ``DesireSummary.preferred``;
- ``false_belief``: ``Estimate.false_belief`` (read against the world at the step).

A smoothed estimate is the person's estimate after their last step at or before the tick
given every step of the episode (:meth:`brain.tracking.tracker.MindTracker.smoothed`; with
lapses on, the online one). Before the person was first seen there is no estimate (``nan``).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from brain.model.arrays import FloatArray
from brain.model.desires import goal_scale, on_scale
from brain.model.estimates import Estimate
from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker

from .judgments import Judgment

__all__ = ["estimate_at", "expected_rank", "goal_scale", "predictions", "rank_of", "read", "utility"]


def estimate_at(
    tracker: MindTracker, person: str, tick: int, smoothed: Sequence[Estimate] | None = None
) -> Estimate | None:
    """The person's estimate after ``tick``: online, or from ``smoothed`` (one per step of
    the person, :meth:`MindTracker.smoothed`); ``None`` before they were first seen."""
    track = tracker.tracks[person]
    ticks = np.array([step.tick for step in track.steps])
    n = int(np.searchsorted(ticks, tick, side="right"))
    if not n:
        return None
    return (track.estimates if smoothed is None else smoothed)[n - 1]


def utility(est: Estimate, settings: ModelSettings) -> FloatArray:
    """``(D,)`` each goal's posterior mean utility on its own scale, in ``[0, 1]`` (P(most
    wanted) for an estimate without a desire summary: the favourite model's reading)."""
    if est.desire is None:
        return est.preference
    return on_scale(est.desire.utility, settings, (0.0, 1.0))


def expected_rank(est: Estimate) -> FloatArray:
    """``(D,)`` each goal's expected rank, 1 the most wanted (ties counting half); without a
    desire summary, the rank of P(most wanted) (ties counting half)."""
    if est.desire is not None:
        above = est.desire.preferred  # (D, D) P(a worth more than b); the diagonal 0.5
        return 0.5 + above.sum(axis=0)
    p = est.preference
    return rank_of(p)


def rank_of(p: FloatArray) -> FloatArray:
    """``(D,)`` the rank of each of ``p`` from the largest (1), ties counting half."""
    greater = (p[None, :] > p[:, None]).sum(axis=1)
    ties = np.isclose(p[None, :], p[:, None]).sum(axis=1) - 1
    return 1.0 + greater + 0.5 * ties


def read(est: Estimate, j: Judgment, settings: ModelSettings) -> float:
    """The value of judgment ``j``'s quantity in ``est``."""
    if j.quantity == "belief":
        return float(est.beliefs[j.index])
    if j.quantity == "desire":
        return float(est.preference[j.index])
    if j.quantity == "utility":
        return float(utility(est, settings)[j.index])
    if j.quantity == "rank":
        return float(expected_rank(est)[j.index])
    return float(est.false_belief[j.index])


def predictions(tracker: MindTracker, judgments: Sequence[Judgment]) -> FloatArray:
    """``(N,)`` the brain's value of each judged quantity (``nan`` before first sight); each
    person's smoothed estimates are computed once, if any judgment asks for them."""
    out = np.full(len(judgments), np.nan)
    smoothed: dict[str, list[Estimate]] = {}
    for n, j in enumerate(judgments):
        if j.estimate == "smoothed" and j.person not in smoothed:
            smoothed[j.person] = tracker.smoothed(j.person) if tracker.tracks[j.person].steps else []
        est = estimate_at(
            tracker, j.person, j.tick, smoothed.get(j.person) if j.estimate == "smoothed" else None
        )
        if est is not None:
            out[n] = read(est, j, tracker.settings)
    return out
