"""The factored model, for houses whose joint over worlds does not fit.

The exact model's hidden state is (believed world, preference) with ``W = V**K`` worlds; a
10-room house with 6 items has ``20**6 = 6.4e7`` of them. The factored model keeps, for
each preference ``d``, one belief per item over its ``V`` values, and assumes:

- **planning**: a person who wants item ``k`` acts on their belief about ``k`` alone. One
  MDP per preference over ``(cell, held, value of the wanted item)`` with held in
  {nothing, the wanted item, another item}: ``S_d = 3 C V`` states instead of ``(K + 1) C W``.
  Taking an item one does not want is left to the likelihood's floor ``epsilon``; a person
  who wants ``out`` plans with no item at all.
- **beliefs**: the paper's update applied to each item on its own (``f = r`` for a change of
  that item's value, when the item is in view or believed to be at a visible place).
- **inference**: given ``d``, the items' beliefs stay independent (an action is evidence
  about the wanted item only), so the posterior is ``alpha[d] * prod_k b[d, k]``. A
  preference switch mixes the conditionals; the mixture is projected back onto per-item
  marginals (assumed-density filtering), the one approximation of the filter itself.

Shapes: ``alpha`` ``(D,)``; ``b`` ``(D, K, V)``; item transitions ``(K, V, V)``; the action
likelihood of one decision ``(D, V)``. The error against the exact model is measured by
``toyroom bench`` (``tv_vs_exact``) wherever the exact model still fits.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
import numpy.typing as npt

from protocol import Scene

from ..settings import ModelSettings
from .arrays import FloatArray, IntArray
from .belief import NOT_IN_VIEW, UNNOTICED, Changes, Percept, changes
from .estimates import Estimate, point_false_belief
from .inference import hazard_matrix
from .planner import (
    HAVE,
    INFEASIBLE,
    TAKE,
    TERMINAL,
    Move,
    Transitions,
    boltzmann,
    drop_action,
    fill_moves,
    n_actions,
    play_action,
    value_iteration,
)
from .world import HELD, RESTING, WorldModel, build_world_model, is_held, location_of, value_of

NOTHING, WANTED, OTHER = 0, 1, 2
"""What a person holds, seen from one preference's MDP."""


def focus_transitions(model: WorldModel, focus: int | None) -> Transitions:
    """The dynamics of one preference's MDP over ``(cell, held in {0, 1, 2}, value)``.

    ``focus`` is the wanted item (``None`` for ``out``: one value, no item to take).
    States ``s = (c * 3 + h) * V + v``; actions as the exact planner's (``A = K + 7``).
    """
    C, K = model.n_cells, model.n_items
    V = model.n_values if focus is not None else 1
    c, h, v = (a.reshape(-1) for a in np.indices((C, 3, V)))
    S, A = C * 3 * V, n_actions(K)

    def index(cells: IntArray, held: IntArray, values: IntArray) -> IntArray:
        return (cells * 3 + held) * V + values

    nxt = np.full((S, A), INFEASIBLE, dtype=np.int64)
    kind = np.zeros((S, A), dtype=np.int8)

    def moved(cells: IntArray) -> IntArray:
        """The wanted item, when carried, follows its carrier to ``cells``."""
        carried = value_of(model.nearest[cells], held=True) if focus is not None else v
        return index(cells, h, np.where(h == WANTED, carried, v))

    fill_moves(model, c, nxt, kind, moved)
    nxt[:, Move.STAY] = np.where(model.outside[c], TERMINAL, index(c, h, v))
    kind[model.outside[c], Move.STAY] = 1
    spot = model.spot_at[c]
    on_spot = spot >= 0
    if focus is not None and model.portable[focus]:  # a fixed item is never taken
        ok = (h == NOTHING) & on_spot & (v == value_of(spot))
        nxt[ok, TAKE + focus] = index(c[ok], np.full(ok.sum(), WANTED), value_of(spot[ok], held=True))
        if model.have_goals:  # taking it is the goal: "have it"
            nxt[ok, TAKE + focus] = TERMINAL
            kind[ok, TAKE + focus] = HAVE
    drop = (h != NOTHING) & on_spot
    dropped = np.where(h == WANTED, value_of(spot), v) if focus is not None else v
    nxt[drop, drop_action(K)] = index(c[drop], np.zeros(drop.sum(), dtype=np.int64), dropped[drop])
    play = (h != NOTHING) & model.play_at[c]
    nxt[play, play_action(K)] = TERMINAL
    kind[play, play_action(K)] = 2
    return Transitions(next_state=nxt, terminal_kind=kind, held=h)


def focus_rewards(trans: Transitions, settings: ModelSettings, wants_item: bool) -> FloatArray:
    """``(S, A)`` rewards of one preference's MDP."""
    utility = np.array(
        [settings.other_utility, settings.preferred_utility, settings.other_utility]
        if wants_item
        else [settings.other_utility] * 3
    )
    reward = np.full(trans.next_state.shape, -settings.step_cost)
    reward[trans.terminal_kind == 1] = (
        settings.leave_utility_item if wants_item else settings.leave_utility_out
    )
    play = trans.terminal_kind == 2
    reward[play] = np.broadcast_to(utility[trans.held][:, None], reward.shape)[play]
    reward[trans.terminal_kind == HAVE] = settings.preferred_utility  # only the wanted item's Take
    return reward


@dataclass(frozen=True)
class FactoredPolicy:
    """The planner's output for the factored model.

    Attributes:
        model: the world model (its ``worlds`` are never built).
        likelihood: ``(D, C, 3, V, A)`` Boltzmann action likelihoods per preference
            (``out``'s does not depend on the value: it is planned with one and broadcast).
        q: ``(D, C, 3, V, A)`` the Q-values behind them (``-inf``: impossible), for people
            who plan with a graded belief (:mod:`brain.model.person.gradedfactored`).
    """

    model: WorldModel
    likelihood: FloatArray
    q: FloatArray

    def relative(self, held: int) -> IntArray:
        """``(D,)`` what a person holding ``held`` (0 nothing, else item index + 1) holds, seen
        from each preference's MDP."""
        D = self.model.n_items + 1
        return np.where(held == 0, NOTHING, np.where(np.arange(D) + 1 == held, WANTED, OTHER))

    def action_likelihood(self, cell: int, held: int, action: int) -> FloatArray:
        """``(D, V)`` likelihood of ``action`` from ``(cell, held)`` (``held``: 0 nothing,
        else item index + 1) for each preference and value of its wanted item."""
        D = self.model.n_items + 1
        return self.likelihood[np.arange(D), cell, self.relative(held), :, action]


def plan_factored(model: WorldModel, settings: ModelSettings) -> FactoredPolicy:
    """Solve one small MDP per preference (no cache; see :func:`cached_factored_policy`)."""
    K, V, C = model.n_items, model.n_values, model.n_cells
    out = np.empty((K + 1, C, 3, V, n_actions(K)))
    qs = np.empty_like(out)
    for d in range(K + 1):
        wants = d < K
        trans = focus_transitions(model, d if wants else None)
        q = value_iteration(
            trans, focus_rewards(trans, settings, wants), settings.discount, settings.vi_tolerance
        )
        out[d] = boltzmann(q, settings.beta, settings.epsilon).reshape(C, 3, V if wants else 1, -1)
        qs[d] = q.reshape(C, 3, V if wants else 1, -1)
    return FactoredPolicy(model=model, likelihood=out, q=qs)


@lru_cache(maxsize=8)
def cached_factored_policy(scene: Scene, settings: ModelSettings) -> FactoredPolicy:
    """The factored policy of a scene, computed once per (scene, settings) in this process."""
    return plan_factored(build_world_model(scene), settings)


class FactoredBeliefs:
    """Each item's belief transition on its own (the paper's update, per item)."""

    def __init__(self, model: WorldModel, r: float, delta: float) -> None:
        self.model = model
        self.r = r
        self.delta = delta
        values = np.arange(model.n_values)
        self.place = location_of(values)
        self.same = values[:, None] == values[None, :]

    def transition(self, p: Percept) -> FloatArray:
        """``(K, V, V)``: ``T[k, i, j] = P(item k believed at value i | j, o)``; columns sum to 1
        (all zero for a value :attr:`WorldModel.value_ok` rules out with no allowed one in reach)."""
        seen = np.array(p.seen, dtype=np.int64)  # (K,)
        visible = self.model.sees[p.cell][self.place]  # (V,)
        values = np.arange(self.model.n_values)
        blind = (seen[:, None] == UNNOTICED) | ~visible[None, :]
        match = np.where(seen[:, None] >= 0, values[None, :] == seen[:, None], blind)  # (K, V)
        likelihood = np.where(match, 1.0 - self.delta, self.delta) * self.model.value_ok  # (K, V)
        ch = changes(self.model, p)
        g = np.where(self.same[None], 1.0, np.where(ch.allowed(), self.r, 0.0))  # (K, V_i, V_j)
        if ch.lost:  # what was carried off is redrawn first
            g = g @ ch.redraw()
        t = likelihood[:, :, None] * g
        total = t.sum(axis=1, keepdims=True)  # 0 for a value ruled out with none in reach
        return t / np.where(total > 0, total, 1.0)

    def revise(
        self, beliefs: FloatArray, p: Percept, *, predict: bool, items: IntArray | None = None
    ) -> FloatArray:
        """``(K, N, V)`` each item's graded beliefs after percept ``p``, by Bayes on the item
        alone: the paper's change weights (1 to stay, ``r`` for a change of a value in view or
        believed visible), each column first normalised when ``predict``, times the percept's
        likelihood; a belief the percept rules out entirely is kept. ``items`` ``(M,)``: the
        items ``beliefs`` ``(M, N, V)`` hold, when not all of them.

        The change matrix of item ``k`` is a diagonal plus a rank-one part (every value it may
        leave goes to every other alike), so the ``(N, V) @ (V, V)`` product is two ``(N, V)``
        passes (:meth:`changed`); only an item redrawn after being carried off
        (:attr:`Changes.lost`) takes its redraw matrix first."""
        K = self.model.n_items
        picked = np.arange(K) if items is None else items
        seen = np.array(p.seen, dtype=np.int64)[picked]
        lost = np.isin(picked, p.lost)
        return self.revise_items(beliefs, p.cell, seen, lost, picked, predict=predict)

    def revise_items(
        self,
        beliefs: FloatArray,
        cell: int,
        seen: IntArray,
        lost: npt.NDArray[np.bool_],
        items: IntArray,
        *,
        predict: bool,
    ) -> FloatArray:
        """:meth:`revise` of ``M`` item beliefs ``(M, N, V)`` of a person on ``cell``, each by
        its own part of a percept: item ``items[m]`` seen as ``seen[m]`` and lost sight of
        in someone's hands (``lost[m]``) or not. An item's revision depends on that part
        alone, so the beliefs of several percepts (a person's lapse rows, each overlooking
        other items) are revised in one pass, the same item more than once."""
        visible = self.model.sees[cell][self.place]
        values = np.arange(self.model.n_values)
        blind = (seen[:, None] == UNNOTICED) | ~visible[None, :]
        match = np.where(seen[:, None] >= 0, values[None, :] == seen[:, None], blind)
        likelihood = np.where(match, 1.0 - self.delta, self.delta) * self.model.value_ok[items]  # (M, V)
        anywhere = (seen[:, None] >= 0) | (visible[None, :] & (seen[:, None] != UNNOTICED))
        carried = lost[:, None] & (seen[:, None] == NOT_IN_VIEW) & is_held(values)[None, :]
        ch = Changes(anywhere, carried, ~visible)
        before = beliefs
        if ch.lost:  # the carried off are redrawn first: b @ R^T
            redraw, before = ch.redraw(), beliefs.copy()
            for m in np.nonzero(carried.any(axis=1))[0]:
                before[m] = beliefs[m] @ redraw[m].T
        new = self.changed(before, anywhere, predict)  # a new array: revised in place
        new *= likelihood[:, None, :]
        total = new.sum(axis=2, keepdims=True)
        ruled_out = total <= 0  # a belief the percept rules out entirely is kept
        new /= np.where(ruled_out, 1.0, total)
        if ruled_out.any():
            np.copyto(new, beliefs, where=ruled_out)
        return new

    def changed(self, beliefs: FloatArray, anywhere: npt.NDArray[np.bool_], predict: bool) -> FloatArray:
        """``(K, N, V)`` ``beliefs`` taken through each item's change weights, ``g[i, j] = 1``
        for ``i = j``, ``r`` for ``i != j`` where ``anywhere[k, j]`` (``(K, V)``), else 0, each
        column divided by its sum when ``predict``: ``b @ g^T = b * d + r (b . u)`` with
        ``u = a / c`` and ``d = (1 - r a) / c`` (``a`` the mask, ``c`` the column sums)."""
        a = anywhere.astype(np.float64)
        c = 1.0 + self.r * (a.shape[1] - 1) * a if predict else np.ones_like(a)  # (K, V)
        u, d = a / c, (1.0 - self.r * a) / c
        moved = self.r * np.einsum("knv,kv->kn", beliefs, u)  # (K, N): the mass each value may leave
        out = beliefs * d[:, None, :]
        out += moved[:, :, None]
        return out

    def true_world(self, truth: tuple[int, ...], p: Percept) -> FloatArray:
        """``(K, V, V)`` transition of an observer who assumes people know the true world."""
        K, V = self.model.n_items, self.model.n_values
        t = np.zeros((K, V, V))
        for k, value in enumerate(truth):
            seen = p.seen[k]
            own = seen >= 0 and is_held(seen) and seen != value  # the person's own carried item
            t[k, seen if own else value, :] = 1.0
        return t


@dataclass(frozen=True)
class FactoredPosterior:
    """A person's posterior in the factored model.

    Attributes:
        alpha: ``(D,)`` preference probabilities.
        beliefs: ``(D, K, V)`` per preference, each item's believed value.
    """

    alpha: FloatArray
    beliefs: FloatArray


def factored_prior(model: WorldModel) -> FactoredPosterior:
    """Uniform over preferences and over every item's allowed values (:attr:`WorldModel.value_ok`:
    a fixed item is never held), the exact model's prior without capacities."""
    D = model.n_items + 1
    ok = model.value_ok.astype(np.float64)  # (K, V)
    per_item = ok / ok.sum(axis=1, keepdims=True)
    return FactoredPosterior(alpha=np.full(D, 1.0 / D), beliefs=np.repeat(per_item[None], D, axis=0))


def factored_step(
    previous: FactoredPosterior, transition: FloatArray, likelihood: FloatArray | None, switch: float
) -> FactoredPosterior:
    """The filtered posterior after one step (:func:`factored_filter_step`)."""
    return factored_filter_step(previous, transition, likelihood, switch)[0]


def factored_filter_step(
    previous: FactoredPosterior, transition: FloatArray, likelihood: FloatArray | None, switch: float
) -> tuple[FactoredPosterior, float]:
    """The filtered posterior after one step and the step's evidence (1 for a percept
    alone), in the exact model's order: the preference switch of the pause before the step,
    the action's likelihood at the previous state, the belief transition of the new percept.

    Args:
        previous: the posterior before the step.
        transition: ``(K, V, V)`` per-item belief transitions.
        likelihood: ``(D, V)`` action likelihood per preference and value of its wanted
            item (``out``'s row is constant), or ``None`` for a percept alone.
        switch: probability that the preference changed in the pause before this step.
    """
    alpha, b = previous.alpha, previous.beliefs
    D, K, _ = b.shape
    if switch > 0 and D > 1:
        h = hazard_matrix(D, switch)
        mixed_alpha = alpha @ h
        b = np.einsum("e,ed,ekv->dkv", alpha, h, b) / mixed_alpha[:, None, None]
        alpha = mixed_alpha / mixed_alpha.sum()
    total = 1.0
    if likelihood is not None:
        items = np.arange(K)
        wanted = b[items, items, :] * likelihood[:K]  # (K, V): each item preference's own item
        evidence = np.append(wanted.sum(axis=1), likelihood[K].mean())
        weighted = alpha * evidence
        total = float(weighted.sum())
        if total > 0:  # else every hypothesis is ruled out: the percept alone
            b = b.copy()
            b[items, items, :] = wanted / np.where(evidence[:K, None] > 0, evidence[:K, None], 1.0)
            alpha = weighted / total
    b = np.einsum("kij,dkj->dki", transition, b)
    return FactoredPosterior(alpha=alpha / alpha.sum(), beliefs=b), total


def factored_intention(alpha: FloatArray, per_item: FloatArray) -> tuple[int | None, int | None, float]:
    """The likeliest (wanted item, where the person believes it is, probability), or ``out``
    (``None, None``) when that is likelier: from ``(D,)`` preferences and ``(D, K, L)`` each
    preference's belief about each item."""
    K = per_item.shape[1]
    best: tuple[int | None, int | None, float] = (None, None, float(alpha[K]))
    for k in range(K):
        joint = alpha[k] * per_item[k, k]
        location = int(np.argmax(joint))
        if joint[location] > best[2]:
            best = (k, location, float(joint[location]))
    return best


def factored_estimate(model: WorldModel, posterior: FactoredPosterior, truth: tuple[int, ...]) -> Estimate:
    """The estimate (same fields as the exact model's) of a factored posterior."""
    alpha, b = posterior.alpha, posterior.beliefs
    by_location = b[..., RESTING] + b[..., HELD]  # (D, K, L): resting at l, or held near it
    beliefs = np.einsum("d,dkl->kl", alpha, by_location)
    return Estimate(
        beliefs=beliefs,
        preference=alpha.copy(),
        intention=factored_intention(alpha, by_location),
        false_belief=point_false_belief(beliefs, truth),
    )
