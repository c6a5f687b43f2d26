"""Belief-space planning: people who plan over what they will see, so that going to look
has value (the faithful option to QMDP; ``ModelSettings.person_planner = "belief"``).

A person's belief about each item is a distribution over the ``L`` resting locations and
one more outcome, *unavailable* (held by someone else: never seen at a spot, never taken),
kept on a finite set of points: the grid of :func:`brain.model.graded.simplex_grid` closed
under what looking does (seeing the item somewhere makes the belief a point; not seeing it
at the visible locations zeroes them and renormalises), so the planner's beliefs stay on
the set exactly. The person plans as if unseen things stay put (no ``r``-weighted moves in
the plan; the update of their belief keeps them). Items are independent given what is seen.

States ``(c, h, i_1, ..., i_K)``: cell, held item (0: nothing), and per item the index of
its belief point (or ``HELD`` when it is the person's own carried item); ``J = (B + 1)^K``
belief states per cell and held item. Arriving at a cell, each item's belief branches over
what is seen there (``T_k[c]``, ``(B + 1, B + 1)`` row-stochastic); a sweep is one batched
matrix product per item axis. Rewards, discount and terminals (Play, Use, leaving) are the point planner's
(:mod:`brain.model.planner`), one MDP per candidate desire. The decision likelihood reads
each hypothesis's belief ``b_g`` as per-item points (the nearest, in total variation).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from protocol import Scene

from ..settings import ModelSettings
from .arrays import TIE, FloatArray, IntArray
from .desires import utilities
from .graded import choice_likelihood, simplex_grid
from .planner import TAKE, Move, drop_action, n_actions, play_action, use_action
from .world import WorldModel, build_world_model


def belief_points(sees: np.ndarray, resolution: int) -> FloatArray:
    """``(B, L + 1)`` the grid over the ``L`` resting locations, the certain points and
    *unavailable*, closed under not seeing the item at each cell's visible locations."""
    L = sees.shape[1]
    start = np.hstack([simplex_grid(L, resolution), np.zeros((len(simplex_grid(L, resolution)), 1))])
    points = {tuple(np.round(p, 12)) for p in np.vstack([start, np.eye(L + 1)])}
    views = {tuple(row) for row in sees}
    frontier = list(points)
    while frontier:
        new = []
        for p in frontier:
            for view in views:
                hidden = np.array([*(not v for v in view), True]) * np.array(p)
                if hidden.sum() > 1e-12 and not np.allclose(hidden, p):
                    q = tuple(np.round(hidden / hidden.sum(), 12))
                    if q not in points:
                        points.add(q)
                        new.append(q)
        frontier = new
    return np.array(sorted(points, reverse=True), dtype=np.float64)


def look_transitions(points: FloatArray, sees: np.ndarray) -> FloatArray:
    """``(C, B + 1, B + 1)`` per cell: from belief point ``i`` (or ``HELD = B``) to what the
    belief is after looking from that cell (the item seen at a visible location, or not)."""
    B, L1 = points.shape
    index = {tuple(np.round(p, 12)): i for i, p in enumerate(points)}
    T = np.zeros((len(sees), B + 1, B + 1))
    T[:, B, B] = 1.0
    for c, view in enumerate(sees):
        visible = np.append(view, False)
        for i, p in enumerate(points):
            for loc in np.flatnonzero(visible & (p > 0)):
                T[c, i, index[tuple(np.eye(L1)[loc])]] += p[loc]
            rest = np.where(visible, 0.0, p)
            if rest.sum() > 1e-12:
                T[c, i, index[tuple(np.round(rest / rest.sum(), 12))]] += rest.sum()
    return T


@dataclass(frozen=True)
class LookaheadPolicy:
    """Belief-space values of one map.

    Attributes:
        model: the world model.
        points: ``(B, L + 1)`` the belief points of one item.
        look: ``(C, B + 1, B + 1)`` what looking from each cell does to one item's belief.
        value: ``(U, C, K + 1, J)`` state values per candidate desire.
        utilities: ``(U, D)`` the candidate desires.
        certain: ``(L,)`` the index of the point "surely at location ``l``".
    """

    model: WorldModel
    points: FloatArray
    look: FloatArray
    value: FloatArray
    utilities: FloatArray
    certain: IntArray
    step_cost: float
    discount: float

    @property
    def held_index(self) -> int:
        return len(self.points)

    @property
    def strides(self) -> IntArray:
        n, K = len(self.points) + 1, self.model.n_items
        return np.array([n ** (K - 1 - k) for k in range(K)], dtype=np.int64)

    def project(self, marginals: FloatArray, held: int) -> IntArray:
        """``(G,)`` belief-state indices of ``(G, K, L + 1)`` per-item beliefs (resting
        locations, then unavailable) of a person holding ``held`` (0: nothing)."""
        distance = np.abs(marginals[:, :, None, :] - self.points[None, None, :, :]).sum(axis=3)  # (G, K, B)
        idx = np.argmax(distance <= distance.min(axis=2, keepdims=True) + TIE, axis=2)  # ties: the first
        if held:
            idx[:, held - 1] = self.held_index
        return idx @ self.strides

    def likelihood(
        self, rest: FloatArray, cell: int, held: int, action: int, beta: float, epsilon: float
    ) -> FloatArray:
        """``(G, U)`` the probability of ``action`` from ``(cell, held)`` for hypotheses whose
        beliefs put each item at each resting location with ``(G, K, L)`` probabilities ``rest``
        (the rest of each item's mass: held by someone, *unavailable*)."""
        marginals = np.concatenate([rest, 1.0 - rest.sum(axis=2, keepdims=True)], axis=2)
        q = self.q_at(cell, held, self.project(np.clip(marginals, 0.0, 1.0), held))
        return choice_likelihood(q, action, beta, epsilon).T

    def arrival(self, cell: int, held: int) -> FloatArray:
        """``(U, J)`` expected value of arriving at ``cell`` holding ``held``, before looking."""
        n, K = len(self.points) + 1, self.model.n_items
        x = self.value[:, cell, held].reshape(-1, *([n] * K))
        for k in range(K):
            x = np.moveaxis(np.tensordot(x, self.look[cell], axes=([1 + k], [1])), -1, 1 + k)
        return x.reshape(len(self.value), -1)

    def q_at(self, cell: int, held: int, states: IntArray) -> FloatArray:
        """``(U, G, A)`` Q-values at ``cell`` holding ``held`` for belief states ``states``
        (``-inf``: impossible)."""
        model, K = self.model, self.model.n_items
        U, G = len(self.value), len(states)
        q = np.full((U, G, n_actions(K)), -np.inf)
        step, gamma = -self.step_cost, self.discount
        for a in range(4):
            nxt = int(model.neighbour[cell, a])
            if nxt < 0:
                continue
            if model.outside[nxt]:
                q[:, :, a] = self.utilities[:, K][:, None]
            else:
                q[:, :, a] = step + gamma * self.arrival(nxt, held)[:, states]
        stay = (
            self.utilities[:, K][:, None]
            if model.outside[cell]
            else step + gamma * self.value[:, cell, held][:, states]
        )
        q[:, :, Move.STAY] = stay
        spot = int(model.spot_at[cell])
        digits = (states[:, None] // self.strides[None, :]) % (len(self.points) + 1)  # (G, K)
        if spot >= 0:
            certain = int(self.certain[spot])
            if held == 0:
                for k in range(K):
                    ok = digits[:, k] == certain
                    after = states + (self.held_index - digits[:, k]) * self.strides[k]
                    q[:, ok, TAKE + k] = step + gamma * self.value[:, cell, k + 1][:, after[ok]]
            else:
                after = states + (certain - digits[:, held - 1]) * self.strides[held - 1]
                q[:, :, drop_action(K)] = step + gamma * self.value[:, cell, 0][:, after]
        if held and model.play_at[cell]:
            q[:, :, play_action(K)] = self.utilities[:, held - 1][:, None]
        if spot >= 0 and model.use_at[cell]:
            for k in range(K):
                ok = digits[:, k] == int(self.certain[spot])
                q[:, ok, use_action(K, k)] = self.utilities[:, k][:, None]
        return q


def _arrivals(value: FloatArray, look: FloatArray, n: int, K: int) -> FloatArray:
    """``(U, C, H, J)``: for every cell, the expected value of arriving there, before looking."""
    U, C, H, _ = value.shape
    x = value.reshape(U, C, H, *([n] * K))
    for k in range(K):
        y = np.moveaxis(np.moveaxis(x, 3 + k, -1), 1, 0)  # (C, U, H, ..., n)
        shape = y.shape
        y = (y.reshape(C, -1, n) @ look.transpose(0, 2, 1)).reshape(shape)
        x = np.moveaxis(np.moveaxis(y, 0, 1), -1, 3 + k)
    return x.reshape(U, C, H, -1)


def solve(model: WorldModel, settings: ModelSettings, max_sweeps: int = 10_000) -> LookaheadPolicy:
    """Value iteration over ``(cell, held, per-item belief points)`` for every candidate desire."""
    K, C, L = model.n_items, model.n_cells, model.n_locations
    points = belief_points(model.sees, settings.prior_resolution)
    look = look_transitions(points, model.sees)
    n, held_index = len(points) + 1, len(points)
    J = n**K
    u = utilities(settings, K, leaves=bool(model.outside.any()))
    eye = np.eye(L + 1)
    certain = np.array([int(np.flatnonzero(np.all(np.isclose(points, eye[i]), axis=1))[0]) for i in range(L)])
    strides = np.array([n ** (K - 1 - k) for k in range(K)], dtype=np.int64)
    digits = (np.arange(J)[:, None] // strides[None, :]) % n  # (J, K)
    step, gamma = -settings.step_cost, settings.discount
    leave = u[:, K][:, None, None, None]
    value = np.zeros((len(u), C, K + 1, J))
    spots = np.flatnonzero(model.spot_at >= 0)
    plays = np.flatnonzero(model.play_at)
    uses = np.flatnonzero(model.use_at & (model.spot_at >= 0))
    for _ in range(max_sweeps):
        arrive = _arrivals(value, look, n, K)
        best = np.where(model.outside[None, :, None, None], leave, step + gamma * value)  # Stay
        for a in range(4):
            nb = model.neighbour[:, a]
            ok = nb >= 0
            safe = np.where(ok, nb, 0)
            moved = np.where(model.outside[safe][None, :, None, None], leave, step + gamma * arrive[:, safe])
            best = np.maximum(best, np.where(ok[None, :, None, None], moved, -np.inf))
        for c in spots:
            there = int(certain[model.spot_at[c]])
            for k in range(K):
                ok = (digits[:, k] == there) & bool(model.portable[k])  # a fixed item is never taken
                after = np.arange(J) + (held_index - digits[:, k]) * strides[k]
                take = step + gamma * value[:, c, k + 1][:, after]
                best[:, c, 0] = np.where(ok[None, :], np.maximum(best[:, c, 0], take), best[:, c, 0])
                dropped = np.arange(J) + (there - digits[:, k]) * strides[k]
                best[:, c, k + 1] = np.maximum(best[:, c, k + 1], step + gamma * value[:, c, 0][:, dropped])
        for c in plays:
            best[:, c, 1:] = np.maximum(best[:, c, 1:], u[:, :K][:, :, None])
        for c in uses:
            there = int(certain[model.spot_at[c]])
            for k in range(K):
                ok = (digits[:, k] == there)[None, None, :]
                best[:, c] = np.where(ok, np.maximum(best[:, c], u[:, k][:, None, None]), best[:, c])
        converged = np.max(np.abs(best - value)) <= settings.vi_tolerance
        value = best
        if converged:
            break
    return LookaheadPolicy(
        model=model,
        points=points,
        look=look,
        value=value,
        utilities=u,
        certain=certain,
        step_cost=settings.step_cost,
        discount=settings.discount,
    )


@lru_cache(maxsize=8)
def cached_lookahead(scene: Scene, settings: ModelSettings) -> LookaheadPolicy:
    """The belief-space policy of a scene, computed once per (scene, settings) in this process."""
    return solve(build_world_model(scene), settings)
