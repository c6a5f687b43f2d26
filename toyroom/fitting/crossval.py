"""k-fold cross-validation by episode over a grid of parameters (pure numpy).

The table of a model is ``ll (P, E)``: the log-likelihood of episode ``e``'s decisions at
grid point ``p``, with ``actions (E,)``. A fold's fit is the point with the largest summed
log-likelihood on the other folds' episodes; its score, the held-out log-likelihood per
action on the fold's own.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import numpy.typing as npt

FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.int64]


@dataclass(frozen=True)
class Fold:
    """One fold: its held-out episodes, the point fitted without them, and the held-out
    log-likelihood (total and per action) at that point."""

    held_out: tuple[int, ...]
    best: int
    log_likelihood: float
    actions: int

    @property
    def per_action(self) -> float:
        return self.log_likelihood / self.actions if self.actions else float("nan")


def folds(episodes: int, k: int, seed: int = 0) -> list[IntArray]:
    """``k`` disjoint sets of episode indices covering ``range(episodes)`` (shuffled by
    ``seed``); ``k`` is at most the number of episodes.

    Raises:
        ValueError: when ``k < 2`` or there are fewer episodes than folds."""
    if k < 2 or episodes < k:
        raise ValueError(f"{k}-fold cross-validation needs k >= 2 and at least k episodes, got {episodes}")
    order = np.random.default_rng(seed).permutation(episodes)
    return [np.sort(part).astype(np.int64) for part in np.array_split(order, k)]


def best_point(ll: FloatArray, episodes: IntArray | None = None) -> int:
    """The grid point with the largest log-likelihood summed over ``episodes`` (all)."""
    chosen = ll if episodes is None else ll[:, episodes]
    return int(np.argmax(chosen.sum(axis=1)))


def cross_validate(ll: FloatArray, actions: IntArray, parts: list[IntArray]) -> list[Fold]:
    """Each fold fitted on the rest and scored on itself."""
    out = []
    everything = np.arange(ll.shape[1])
    for part in parts:
        train = np.setdiff1d(everything, part)
        best = best_point(ll, train)
        out.append(
            Fold(tuple(int(e) for e in part), best, float(ll[best, part].sum()), int(actions[part].sum()))
        )
    return out


def held_out_per_action(result: list[Fold]) -> float:
    """The held-out log-likelihood per action over every fold (pooled)."""
    actions = sum(f.actions for f in result)
    return sum(f.log_likelihood for f in result) / actions if actions else float("nan")
