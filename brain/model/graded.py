"""Graded beliefs: each person holds their own distribution over worlds (Baker, Saxe and
Tenenbaum 2011; Baker, Jara-Ettinger, Saxe and Tenenbaum 2017), updated by Bayes from their
own percepts, and acts on it by QMDP.

The robot cannot see a person's initial belief, so it keeps ``G`` hypotheses: for each item,
every point of a grid over the simplex of its resting locations (resolution ``n``: the
probabilities ``c / n``), and the product over items, weighed given where the items are at
the person's first sight (:class:`InitialBeliefs`, :func:`informed_weights`). Each
hypothesis ``g`` holds a belief ``b_g`` over the ``W`` worlds that evolves deterministically
with the person's percepts:

    predict   b(i) ∝ P(o | x, w^i) sum_j [g(i, j) / sum_i' g(i', j)] b(j)   (the default)
    paper     b(i) ∝ P(o | x, w^i) sum_j  g(i, j) b(j)                        (one normalisation)

with the paper's ``g`` (1 to stay, ``r`` for a change inside ``PW(j)``, 0 outside), so ``r`` is
the prior weight a person gives to "it was moved" against "it was there all along". A
decision's likelihood is QMDP: the Boltzmann choice over the expected Q-values under the
person's belief, an action that is impossible in a world doing what Stay does there:

    P(a | x, h, b, d) = (1 - epsilon) softmax_a(beta sum_w b(w) Q_d(x, h, w, a)) + epsilon / A

The robot's posterior is over ``(g, d)``; what it reports as the person's belief is the
expectation ``sum_{g,d} P(g, d) b_g`` (a ``(W, D)`` joint, read like the point model's).
Everything here is pure: numpy arrays in, arrays out.
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence

import numpy as np
import numpy.typing as npt

from ..settings import ModelSettings
from .arrays import FloatArray
from .belief import BeliefModel, Percept
from .mixture import Beliefs, Mixture
from .person.remembered import hypothesis_weights
from .planner import Move
from .world import RESTING, VALUES_PER_LOCATION, WorldModel, location_of

UPDATES = ("predict", "paper")
"""The person's own belief update: predict-then-correct (default), or the paper's literal
single normalisation."""


def simplex_grid(size: int, resolution: int) -> FloatArray:
    """``(P, size)`` every distribution over ``size`` outcomes whose probabilities are
    multiples of ``1 / resolution`` (``resolution = 1``: the certain ones)."""
    points = [
        np.bincount(np.array(combo, dtype=np.int64), minlength=size) / resolution
        for combo in itertools.combinations_with_replacement(range(size), resolution)
    ]
    return np.array(points, dtype=np.float64)


def initial_points(n_locations: int, resolution: int, ignorance: float) -> tuple[FloatArray, FloatArray]:
    """``(P, L)`` the hypotheses of a person's initial belief about one item and ``(P,)``
    their prior weights: the grid points (:func:`simplex_grid`) sharing ``1 - ignorance``,
    and the uniform belief (not knowing where it is) with ``ignorance`` (the grid's point
    when the grid holds it)."""
    points = simplex_grid(n_locations, resolution)
    uniform = np.full(n_locations, 1.0 / max(n_locations, 1))
    at = np.flatnonzero(np.abs(points - uniform).max(axis=1) < 1e-12)
    if ignorance > 0 and not len(at):
        points, at = np.vstack([points, uniform]), np.array([len(points)])
    weights = np.zeros(len(points))
    rest = np.ones(len(points), dtype=bool)
    if ignorance > 0:
        weights[at] = ignorance
        rest[at] = False
    weights[rest] = (1.0 - ignorance if ignorance > 0 else 1.0) / max(int(rest.sum()), 1)
    return points, weights


def informed_weights(points: FloatArray, ignorance: float, stale: float, true_location: int) -> FloatArray:
    """``(P,)`` the prior weights of ``(P, L)`` points (:func:`initial_points`) as a person's
    initial belief about an item that is at ``true_location`` when they are first seen.

    The uniform belief keeps ``ignorance`` and the grid's points share the rest evenly, as in
    :func:`initial_points`, except that the points giving the true location nothing (a
    belief from before the episode that has gone out of date) get at most the share
    ``stale`` of it, the others the remainder. The grid alone gives those points the share
    ``(L - 1) / (L - 1 + n)``, which nears one as locations are added, so that almost every
    person with an opinion would hold a false one; with the cap the prior probability of a
    false belief is at most ``(1 - ignorance) stale`` whatever ``L`` (on up to 4 locations at
    ``n = 2`` the grid's share is at most 0.6, the default ``stale``: unchanged)."""
    uniform = (np.abs(points - 1.0 / points.shape[1]).max(axis=1) < 1e-12) & (ignorance > 0)
    wrong = ~uniform & (points[:, true_location] <= 0)
    right = ~uniform & ~wrong
    definite = 1.0 - ignorance if ignorance > 0 else 1.0
    n_wrong, n_right = int(wrong.sum()), int(right.sum())
    stale_mass = definite * min(n_wrong / max(n_wrong + n_right, 1), stale if n_right else 1.0)
    weights = np.where(uniform, ignorance, 0.0)
    weights[wrong] = stale_mass / max(n_wrong, 1)
    weights[right] = (definite - stale_mass) / max(n_right, 1)
    return weights / weights.sum()


def hypothesis_combos(n_items: int, n_points: int) -> npt.NDArray[np.int64]:
    """``(G, K)`` the point of each item in every hypothesis (``G = P**K``, item 0 slowest)."""
    return np.array(list(itertools.product(range(n_points), repeat=n_items)), dtype=np.int64).reshape(
        -1, n_items
    )


def prior_beliefs(
    worlds: np.ndarray, n_locations: int, resolution: int, ignorance: float = 0.0
) -> tuple[FloatArray, FloatArray]:
    """``(G, W)`` the hypotheses of a person's initial belief and ``(G,)`` their prior
    weights: per item a point of :func:`initial_points` over its resting locations (never
    held by someone else), independent across items.

    Args:
        worlds: ``(W, K)`` every world's item values ``2 l + held``.
        n_locations: ``L``, the number of item locations.
        resolution: the grid's resolution ``n``.
        ignorance: the prior weight, per item, of the uniform belief.
    """
    points, point_weights = initial_points(n_locations, resolution, ignorance)  # (P, L), (P,)
    per_value = np.zeros((len(points), VALUES_PER_LOCATION * n_locations))
    per_value[:, RESTING] = points
    n_items = worlds.shape[1]
    combos = hypothesis_combos(n_items, len(points))
    beliefs = np.ones((len(combos), len(worlds)))
    weights = np.ones(len(combos))
    for k in range(n_items):
        beliefs *= per_value[combos[:, k]][:, worlds[:, k]]
        weights *= point_weights[combos[:, k]]
    return beliefs, weights


class InitialBeliefs:
    """The hypotheses of a person's initial belief in one scene (:func:`prior_beliefs`), less
    those a location's capacity rules out, and their prior weights given the world at the
    person's first sight (:func:`informed_weights`).

    Attributes:
        beliefs: ``(G, W)`` each hypothesis's belief.
        weights: ``(G,)`` the grid's own weights (uniform over its points), whatever the truth.
        combos: ``(G, K)`` each hypothesis's point per item.
        points: ``(P, L)`` one item's points.
    """

    def __init__(self, model: WorldModel, settings: ModelSettings) -> None:
        resolution, ignorance = settings.prior_resolution, settings.ignorance
        self.points, self.point_weights = initial_points(model.n_locations, resolution, ignorance)
        beliefs, weights = prior_beliefs(model.worlds, model.n_locations, resolution, ignorance)
        beliefs = beliefs * model.allowed[None, :]  # no belief in a world a capacity rules out
        total = beliefs.sum(axis=1, keepdims=True)
        keep = (total[:, 0] > 0) & (weights > 0)
        self.beliefs: FloatArray = beliefs[keep] / total[keep]
        self.weights: FloatArray = weights[keep] / weights[keep].sum()
        self.combos = hypothesis_combos(model.n_items, len(self.points))[keep]
        self.ignorance, self.stale = ignorance, settings.stale_share
        self._given: dict[tuple[int, ...], FloatArray] = {}

    def remembered(
        self, truth: tuple[int, ...] | None, memory: Sequence[FloatArray | None], settings: ModelSettings
    ) -> FloatArray:
        """``(G,)`` the prior weights of a person remembered from an earlier day to believe each
        item at each location with ``memory[k]`` ``(L,)`` (``None``: not remembered): each
        item's point weights (:func:`informed_weights` given ``truth``, else the grid's own)
        weighed by the memory (:func:`~brain.model.person.remembered.hypothesis_weights`)."""
        places = [None] * len(memory) if truth is None else [location_of(v) for v in truth]
        bases = [
            self.point_weights
            if place is None
            else informed_weights(self.points, self.ignorance, self.stale, place)
            for place in places
        ]
        return hypothesis_weights(
            self.combos, self.points, bases, memory, settings.memory_strength, settings.memory_forget
        )

    def given(self, truth: tuple[int, ...]) -> FloatArray:
        """``(G,)`` the prior weights when the items' true values (``2 l + held``) are
        ``truth`` at the person's first sight: per item :func:`informed_weights`, multiplied."""
        places = tuple(location_of(value) for value in truth)
        if places not in self._given:
            weights = np.ones(len(self.combos))
            for k, place in enumerate(places):
                weights *= informed_weights(self.points, self.ignorance, self.stale, place)[self.combos[:, k]]
            self._given[places] = weights / weights.sum()
        return self._given[places]


def update_beliefs(beliefs: FloatArray, model: BeliefModel, p: Percept, rule: str = "predict") -> FloatArray:
    """``(G, W)`` every hypothesis's belief after percept ``p`` (rows sum to one)."""
    new = unnormalised_update(beliefs, model, p, rule)
    total = new.sum(axis=1, keepdims=True)
    new /= np.where(total > 0, total, 1.0)
    impossible = total[:, 0] <= 0  # a percept no world of the hypothesis explains: kept as it was
    if impossible.any():
        new[impossible] = beliefs[impossible]
    return new


def unnormalised_update(
    beliefs: FloatArray, model: BeliefModel, p: Percept, rule: str = "predict"
) -> FloatArray:
    """``(N, W)`` the linear part of :func:`update_beliefs` (the change, then the percept's
    likelihood; rows not normalised), as a new array: callers may change it in place."""
    if rule not in UPDATES:
        raise ValueError(f"unknown belief update {rule!r}; known: {', '.join(UPDATES)}")
    new = model.apply_change(beliefs, p, predict=rule == "predict")  # a new array: updated in place
    new *= model.percept_likelihood(p)[None, :]
    return new


def drift(beliefs: FloatArray, n_items: int, n_values: int, mass: float) -> FloatArray:
    """``(G, W)`` beliefs after forgetting: each item believed resting moves to a resting
    location drawn uniformly with probability ``mass`` (``p <- (1 - mass) p + mass / L`` on
    each item's marginal, as ``--minds rich`` people forget); a carried item stays carried.
    One ``(V, V)`` product per item axis, never a ``(W, W)`` matrix."""
    if mass <= 0:
        return beliefs
    V, K = n_values, n_items
    resting = np.arange(V)[RESTING]
    move = np.eye(V)
    move[:, resting] *= 1.0 - mass
    move[np.ix_(resting, resting)] += mass / len(resting)  # move[i, j]: from value j to i
    tensor = beliefs.reshape(len(beliefs), *([V] * K))
    for k in range(K):
        tensor = np.moveaxis(np.tensordot(tensor, move, axes=([1 + k], [1])), -1, 1 + k)
    return tensor.reshape(len(beliefs), -1)


def qmdp_likelihood(beliefs: Beliefs, q: FloatArray, action: int, beta: float, epsilon: float) -> FloatArray:
    """``(G, U)`` the probability of ``action`` for each hypothesis and candidate desire.

    Args:
        beliefs: ``(G, W)`` the person's belief under each hypothesis.
        q: ``(U, W, A)`` the planner's Q-values at the person's cell and held item, per
            preference and world (``-inf``: impossible in that world).
        action: the action taken.
        beta: the Boltzmann rationality the likelihood softmaxes the Q-values with.
        epsilon: the chance of an action taken at random, mixed in evenly.
    """
    values = expected_q_by_action(beliefs, q)  # (A, U, G)
    return choice_likelihood(values, action, beta, epsilon, axis=0).T


def expected_q_by_action(beliefs: Beliefs, q: FloatArray) -> FloatArray:
    """``(A, U, N)`` :func:`expected_q` of ``(N, W)`` beliefs over ``(U, W, A)`` Q-values, laid
    out actions first (the same numbers to rounding): a choice over the actions then reduces
    whole ``(U, N)`` slabs, where numpy's reductions over a short last axis are ten times
    slower. One ``(A U, W) @ (W, N)`` product, and one per distinct feasibility row."""
    U, W, A = q.shape
    rows = np.ascontiguousarray(q.transpose(2, 0, 1)).reshape(A * U, W)  # (A U, W)
    feasible = np.isfinite(rows)
    stay = rows[Move.STAY * U : (Move.STAY + 1) * U]  # (U, W)
    fallback = np.tile(np.where(np.isfinite(stay), stay, 0.0), (A, 1))
    expected = times_transpose(np.where(feasible, rows, fallback), beliefs)  # (A U, N)
    packed = np.packbits(feasible, axis=1)  # (A U, ceil(W / 8)): a row's bits
    keys = packed.view(np.dtype((np.void, packed.shape[1]))).ravel()
    _, first, inverse = np.unique(keys, return_index=True, return_inverse=True)
    mass = times_transpose(feasible[first].astype(np.float64), beliefs)  # (distinct rows, N)
    possible = (mass > 1e-12)[inverse.reshape(-1)]
    return np.where(possible, expected, -np.inf).reshape(A, U, len(beliefs))


def times_transpose(matrix: FloatArray, beliefs: Beliefs) -> FloatArray:
    """``(X, N)`` a ``(X, W)`` matrix times the transpose of ``(N, W)`` beliefs (or of their
    mixture)."""
    if isinstance(beliefs, Mixture):
        return (matrix @ beliefs.vectors.T) @ beliefs.weights.T
    return matrix @ beliefs.T


def expected_q(beliefs: Beliefs, q: FloatArray) -> FloatArray:
    """``(N, ..., A)`` QMDP's expected Q-values of ``(N, W)`` beliefs over ``(W, ..., A)``
    Q-values: an action impossible in a world counts what Stay does there, and an action
    impossible in every believed world is ``-inf``. One ``(N, W) @ (W, M)`` matrix product
    each (BLAS), not an einsum over four indices."""
    W = q.shape[0]
    feasible = np.isfinite(q)
    stay = q[..., Move.STAY]
    values = np.where(feasible, q, np.where(np.isfinite(stay), stay, 0.0)[..., None])
    shape = (len(beliefs), *q.shape[1:])
    expected = (beliefs @ values.reshape(W, -1)).reshape(shape)
    possible = believed_possible(beliefs, feasible.reshape(W, -1)).reshape(shape)
    return np.where(possible, expected, -np.inf)


def believed_possible(beliefs: Beliefs, feasible: npt.NDArray[np.bool_]) -> npt.NDArray[np.bool_]:
    """``(N, M)`` whether each of ``(N, W)`` beliefs puts mass (above ``1e-12``) on the worlds
    where each of ``M`` things is possible (``(W, M)``). One product per distinct column: an
    action's feasibility depends on the world, not on the desire, and most actions are
    possible in every world or in the same few, so a handful of columns serve them all."""
    packed = np.ascontiguousarray(np.packbits(feasible, axis=0).T)  # (M, ceil(W / 8)): a column's bits
    keys = packed.view(np.dtype((np.void, packed.shape[1]))).ravel()  # np.unique(axis=1) is 30x slower
    _, first, inverse = np.unique(keys, return_index=True, return_inverse=True)
    mass = beliefs @ feasible[:, first].astype(np.float64)  # (N, distinct columns)
    return (mass > 1e-12)[:, inverse.reshape(-1)]


def choice_likelihood(
    q: FloatArray, action: int, beta: float | FloatArray, epsilon: float | FloatArray, axis: int = -1
) -> FloatArray:
    """``q``'s shape less ``axis``: the Boltzmann probability of ``action`` over the actions
    on ``axis`` of ``q`` (``-inf``: impossible), with the floor ``epsilon`` spread over every
    action."""
    weights = beta * q
    top = weights.max(axis=axis, keepdims=True)
    top[~np.isfinite(top)] = 0.0  # every action impossible: all weights come out 0
    weights -= top
    possible = np.isfinite(weights)  # exp only there: numpy's exp is slow on -inf, most entries
    np.exp(weights, out=weights, where=possible)
    np.copyto(weights, 0.0, where=~possible)
    total = weights.sum(axis=axis)
    chosen = np.take(weights, action, axis=axis)
    soft = np.where(total > 0, chosen / np.where(total > 0, total, 1.0), 0.0)
    return (1.0 - epsilon) * soft + epsilon / q.shape[axis]


def expected_joint(beliefs: Beliefs, posterior: FloatArray) -> FloatArray:
    """``(W, D)`` the person's belief and preference as the robot expects them:
    ``sum_g P(g, u) b_g(w)``, from ``(G, W)`` beliefs (or their mixture) and the ``(G, U)``
    posterior."""
    if isinstance(beliefs, Mixture):
        return beliefs.joint(posterior)
    return beliefs.T @ posterior
