"""Graded beliefs for houses whose joint over worlds does not fit: the factored model's
assumptions (:mod:`brain.model.factored`) with each person's own belief per item graded.

Each item ``k`` has ``P`` hypotheses of the person's initial belief about it (the grid of
:func:`brain.model.graded.simplex_grid` over its resting locations, weighed by
:func:`brain.model.graded.informed_weights` at the person's first step), each carrying the
person's own belief ``beta[k, p]`` over the item's ``V`` values, revised by Bayes from
their percepts on that item alone (:meth:`FactoredBeliefs.revise`). A person who wants item
``k`` plans with their belief about ``k`` alone, by QMDP over the factored planner's
Q-values of that item's MDP. The robot's posterior is ``alpha[d] * prod_k w[d, k, p_k]``:
given the preference the items' hypotheses are independent, an action is evidence about
the wanted item's hypothesis only, and a preference switch mixes the per-preference
weights, projected back onto per-item ones (assumed-density filtering, as the factored
model does); it is smoothed in the same product form (:mod:`brain.model.factoredsmoother`).
Shapes: ``alpha`` ``(D,)``, ``w`` ``(D, K, P)``, ``beta``
``(K, P, V)``. The error against the exact graded model is measured by ``toyroom bench``.

Each item's ``(P, V)`` beliefs are an :class:`SharedItemBelief`, shared by every filter that holds
the same (the rows of a person's lapses, :mod:`brain.model.person.lapses`, and of the factored
unseen world, :mod:`brain.tracking.personrows`, differ in a few items only): its revision by a
percept of the item and its decision likelihoods are worked out once for all of them.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from protocol import Scene, is_false_belief

from ...settings import ModelSettings
from ..arrays import FloatArray, IntArray
from ..belief import Percept
from ..desires import Desires, favourite_utilities
from ..estimates import Estimate
from ..factored import FactoredBeliefs, FactoredPolicy, cached_factored_policy, factored_intention
from ..factoredsmoother import BackwardStep, ProductPosterior, smooth_products
from ..graded import choice_likelihood, informed_weights, initial_points
from ..inference import hazard_matrix, log_of
from ..planner import Move
from ..world import HELD, RESTING, location_of
from .personinterface import StepRecord


@dataclass(eq=False)
class SharedItemBelief:
    """One item's beliefs under each of the ``P`` hypotheses, ``values`` ``(P, V)``, never
    changed once made: filters holding the same share it, and what is worked out of it is
    kept on it for the others (a successor lives as long as some filter holds it or its
    predecessor, one step)."""

    values: FloatArray
    successors: dict[tuple[int, int, int, bool], SharedItemBelief] = field(default_factory=dict)
    """``(item, cell, seen, lost)`` -> the item's beliefs after that percept of it."""
    decisions: dict[tuple[int, int, int, int], FloatArray] = field(default_factory=dict)
    """``(item, cell, held, action)`` -> ``(P,)`` the QMDP probability of that decision for a
    person who wants the item."""
    tables: dict[float, FloatArray] = field(default_factory=dict)
    """``mass`` -> :meth:`false`."""

    @cached_property
    def own(self) -> FloatArray:
        """``(P, L)`` each hypothesis's belief about the item's location: resting + held."""
        return self.values[:, RESTING] + self.values[:, HELD]

    def false(self, mass: float) -> FloatArray:
        """``(P, L)`` 1 where a hypothesis's belief is false were the item at ``l``
        (:func:`protocol.is_false_belief`, ``mass``: ``ModelSettings.false_belief_mass``)."""
        kept = self.tables.get(mass)
        if kept is None:
            own = self.own
            kept = is_false_belief(own, own.max(axis=1, keepdims=True), mass).astype(np.float64)
            self.tables[mass] = kept
        return kept


def stacked(items: Sequence[SharedItemBelief]) -> FloatArray:
    """``(K, P, V)`` the items' beliefs."""
    return np.stack([i.values for i in items])


class GradedFactoredModel:
    """The factored model with graded beliefs; ``true_world``: people know the true world."""

    exact = False

    def __init__(self, scene: Scene, settings: ModelSettings, true_world: bool) -> None:
        self.policy: FactoredPolicy = cached_factored_policy(scene, settings)
        self.model = self.policy.model
        self.settings = settings
        self.true_world = true_world
        self.beliefs = FactoredBeliefs(self.model, settings.r, settings.delta)
        self.desires = Desires(favourite_utilities(settings, self.model.n_items))
        self.points, self.point_weights = initial_points(
            self.model.n_locations, settings.prior_resolution, settings.ignorance
        )  # (P, L), (P,)
        self.initial = np.zeros((len(self.points), self.model.n_values))
        self.initial[:, RESTING] = self.points

    def prior(self, truth: tuple[int, ...]) -> FloatArray:
        """``(K, P)`` each item's hypotheses' prior weights given the true item values at the
        person's first sight (:func:`brain.model.graded.informed_weights`)."""
        ignorance, stale = self.settings.ignorance, self.settings.stale_share
        places = [location_of(value) for value in truth]
        return np.stack([informed_weights(self.points, ignorance, stale, place) for place in places])

    def new_filter(self) -> GradedFactoredFilter:
        K, P = self.model.n_items, len(self.initial)
        D = K + 1
        return GradedFactoredFilter(
            owner=self,
            alpha=np.full(D, 1.0 / D),
            weights=np.broadcast_to(self.point_weights, (D, K, P)).copy(),
            items=(SharedItemBelief(self.initial),) * K,  # every item's alike: shared
        )

    def likelihood(self, cell: int, held: int, action: int) -> FloatArray:
        """The point factored model's ``(D, V)`` likelihood (kept in the record)."""
        return self.policy.action_likelihood(cell, held, action)

    def decision_likelihood(
        self, items: Sequence[SharedItemBelief], cell: int, held: int, action: int
    ) -> FloatArray:
        """``(D, P)`` the QMDP probability of ``action`` for each preference and hypothesis of
        its wanted item (``out``: the same for every hypothesis); each item's row is kept on its
        :class:`SharedItemBelief`, and the items not yet worked out are in one batched product."""
        K = self.model.n_items
        keys = [(k, cell, held, action) for k in range(K)]
        missing = np.array([k for k in range(K) if keys[k] not in items[k].decisions], dtype=np.int64)
        if len(missing):
            rows = self.wanted_likelihood(stacked([items[k] for k in missing]), missing, cell, held, action)
            for k, row in zip(missing, rows, strict=True):
                items[k].decisions[keys[k]] = row
        q = self.policy.q[K, cell, self.policy.relative(held)[K], 0]  # (A,) out's
        out = np.empty((K + 1, len(items[0].values)))
        out[:K] = [items[k].decisions[keys[k]] for k in range(K)]
        out[K] = choice_likelihood(q, action, self.settings.beta, self.settings.epsilon)
        return out

    def wanted_likelihood(
        self, beliefs: FloatArray, items: IntArray, cell: int, held: int, action: int
    ) -> FloatArray:
        """``(M, P)`` the QMDP probability of ``action`` for a person who wants each of
        ``items`` ``(M,)``, per hypothesis: the items' ``(M, P, V)`` beliefs times their
        ``(V, A)`` Q-values in one batched product."""
        q = self.policy.q[items, cell, self.policy.relative(held)[items]]  # (M, V, A)
        feasible = np.isfinite(q)
        stay = q[:, :, Move.STAY]
        values = np.where(feasible, q, np.where(np.isfinite(stay), stay, 0.0)[..., None])
        possible = beliefs @ feasible.astype(np.float64) > 1e-12  # (M, P, A)
        expected = np.where(possible, beliefs @ values, -np.inf)
        return choice_likelihood(expected, action, self.settings.beta, self.settings.epsilon)

    def revise(
        self, items: Sequence[SharedItemBelief], truth: tuple[int, ...], percept: Percept
    ) -> tuple[SharedItemBelief, ...]:
        """Every item's hypotheses after the percept (to the true world for ``true_world``);
        an item's revision by the same percept of it is kept on its :class:`SharedItemBelief`."""
        if self.true_world:
            moved = np.einsum("kij,knj->kni", self.beliefs.true_world(truth, percept), stacked(items))
            return tuple(SharedItemBelief(b) for b in moved)
        lost = set(percept.lost)
        keys = [(k, percept.cell, percept.seen[k], k in lost) for k in range(len(items))]
        missing = np.array(
            [k for k, key in enumerate(keys) if key not in items[k].successors], dtype=np.int64
        )
        if len(missing):
            predict = self.settings.belief_update == "predict"
            new = self.beliefs.revise(
                stacked([items[k] for k in missing]), percept, predict=predict, items=missing
            )
            for k, b in zip(missing, new, strict=True):
                items[k].successors[keys[k]] = SharedItemBelief(b)
        return tuple(items[k].successors[key] for k, key in enumerate(keys))

    def smoothed(
        self, records: Sequence[StepRecord], online: Sequence[Estimate], lag: int | None = None
    ) -> list[Estimate]:
        """Each step's estimate given every step (``lag``: given the next ``lag`` only), by
        forward-backward over the hypotheses' weights (:mod:`brain.model.factoredsmoother`);
        a hypothesis's own belief follows the percepts whatever the weights, so it is replayed."""
        run, forward, likelihoods = self.new_filter(), [], []
        for record in records:
            likelihoods.append(run.advance(record))
            forward.append(ProductPosterior(run.alpha, run.weights))

        def step_at(t: int) -> BackwardStep:
            return BackwardStep(likelihoods[t], records[t].switch)

        smoothed = smooth_products(forward, step_at, lag)
        items, out = self.new_filter().items, []
        for record, posterior, est in zip(records, smoothed, online, strict=True):
            items = self.revise(items, record.truth, record.percept)
            read = self.read(posterior.alpha, posterior.weights, items, record.truth)
            out.append(dataclasses.replace(read, log_evidence=est.log_evidence))
        return out

    def read(
        self,
        alpha: FloatArray,
        weights: FloatArray,
        items: Sequence[SharedItemBelief],
        truth: tuple[int, ...],
    ) -> Estimate:
        """The estimate of a posterior ``alpha`` ``(D,)``, ``weights`` ``(D, K, P)`` over the
        hypotheses whose own beliefs are ``items`` (``K`` of ``(P, V)``)."""
        mass = self.settings.false_belief_mass
        own = np.stack([i.own for i in items])  # (K, P, L) each hypothesis's own: resting + held
        per_item = (weights.transpose(1, 0, 2) @ own).transpose(1, 0, 2)  # (D, K, L), batched over k
        hypotheses = np.tensordot(alpha, weights, axes=1)  # (K, P)
        table = np.einsum("kp,kpl->kl", hypotheses, np.stack([i.false(mass) for i in items]))
        true = location_of(np.array(truth, dtype=np.int64))
        return Estimate(
            beliefs=np.tensordot(alpha, per_item, axes=1),
            preference=alpha.copy(),
            intention=factored_intention(alpha, per_item),
            false_belief=table[np.arange(len(true)), true],
            hypotheses=(hypotheses, own),
            desire=self.desires.summarise(alpha),
            false_table=table,
        )


@dataclass
class GradedFactoredFilter:
    """The graded factored forward pass of one person."""

    owner: GradedFactoredModel
    alpha: FloatArray
    weights: FloatArray
    items: tuple[SharedItemBelief, ...]
    """Each item's beliefs (shared with other filters: never changed, replaced)."""
    log_evidence: float = 0.0
    started: bool = False
    """Whether a step was taken: the first sets the prior by the world then."""

    def __deepcopy__(self, memo: dict[int, object]) -> GradedFactoredFilter:
        """A copy for another row (lapses, :mod:`brain.model.person.lapses`; the factored unseen
        world's, :mod:`brain.tracking.personrows`): arrays of its own, the model shared (a deep
        copy would copy its Q-values: 6.6 s of 10 on a 20-room house's first 100 ticks); the
        items' beliefs, never changed, shared."""
        return dataclasses.replace(self, alpha=self.alpha.copy(), weights=self.weights.copy())

    @property
    def beliefs(self) -> FloatArray:
        """``(K, P, V)`` each item's beliefs under each hypothesis."""
        return stacked(self.items)

    def step(self, record: StepRecord) -> None:
        self.advance(record)

    def advance(self, record: StepRecord) -> FloatArray | None:
        """One step; returns the decision's ``(D, P)`` likelihood (``None`` for a percept alone)."""
        if not self.started:
            self.weights = np.broadcast_to(self.owner.prior(record.truth), self.weights.shape).copy()
            self.started = True
        switch = record.switch  # the pause before the step: before its decision's likelihood
        D = len(self.alpha)
        if switch > 0 and D > 1:
            h = hazard_matrix(D, switch)
            mixed = self.alpha @ h
            joint = h.T @ (self.alpha[:, None] * self.weights.reshape(D, -1))  # (D, K P)
            self.weights = joint.reshape(self.weights.shape) / mixed[:, None, None]
            self.alpha = mixed / mixed.sum()
        likelihood = None
        if record.decision is not None:
            likelihood = self.owner.decision_likelihood(self.items, *record.decision)  # (D, P)
        if record.said is not None:  # the person's answer: evidence over the preference alone
            said = record.said[:, None]
            likelihood = (
                np.repeat(said, self.weights.shape[-1], axis=1) if likelihood is None else likelihood * said
            )
        if likelihood is not None:
            K = self.owner.model.n_items
            items = np.arange(K)
            wanted = self.weights[items, items] * likelihood[:K]  # (K, P)
            evidence = np.append(wanted.sum(axis=1), likelihood[K].mean())
            weighted = self.alpha * evidence
            if record.decision is not None:
                self.log_evidence += log_of(float(weighted.sum()))
            if weighted.sum() > 0:
                self.weights = self.weights.copy()
                self.weights[items, items] = wanted / np.where(
                    evidence[:K, None] > 0, evidence[:K, None], 1.0
                )
                self.alpha = weighted / weighted.sum()
        self.items = self.owner.revise(self.items, record.truth, record.percept)
        return likelihood

    def estimate(self, truth: tuple[int, ...]) -> Estimate:
        est = self.owner.read(self.alpha, self.weights, self.items, truth)
        return dataclasses.replace(est, log_evidence=self.log_evidence)
