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
    readouts: dict[float, FloatArray] = field(default_factory=dict)
    """``mass`` -> :meth:`readout`."""

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

    def readout(self, mass: float) -> FloatArray:
        """``(P, 2 L)`` :attr:`own` beside :meth:`false`: what a hypotheses' weighting of the
        item is read through (its believed locations, its false-belief table), in one product."""
        kept = self.readouts.get(mass)
        if kept is None:
            kept = self.readouts[mass] = np.concatenate([self.own, self.false(mass)], axis=1)
        return kept


def read_out(beliefs: Sequence[SharedItemBelief], mass: float) -> None:
    """Work out, in one pass, :meth:`SharedItemBelief.readout` of each of ``beliefs`` that lacks
    it (the same numbers, element by element)."""
    todo = [b for b in beliefs if mass not in b.readouts]
    if not todo:
        return
    values = stacked(todo)  # (M, P, V)
    own = values[:, :, RESTING] + values[:, :, HELD]  # (M, P, L)
    false = is_false_belief(own, own.max(axis=2, keepdims=True), mass).astype(np.float64)
    for b, table in zip(todo, np.concatenate([own, false], axis=2), strict=True):
        b.readouts[mass] = table


def stacked(items: Sequence[SharedItemBelief]) -> FloatArray:
    """``(K, P, V)`` the items' beliefs."""
    return np.stack([i.values for i in items])


Holders = list[list[tuple[SharedItemBelief, "IntArray | slice"]]]
"""Per item ``k``, its distinct beliefs among some rows, each with the rows holding it
(:func:`holders`)."""


def holders(items: Sequence[Sequence[SharedItemBelief]]) -> Holders:
    """Per item, its distinct beliefs among rows' ``items`` (each row's ``K``), each with the
    ``(n,)`` indices of the rows holding it (in the order first held; ``slice(None)`` when
    every row holds it)."""
    found: list[dict[int, tuple[SharedItemBelief, list[int]]]] = [{} for _ in items[0]]
    for r, row in enumerate(items):
        for per_item, belief in zip(found, row, strict=True):
            entry = per_item.get(id(belief))
            if entry is None:
                per_item[id(belief)] = (belief, [r])
            else:
                entry[1].append(r)
    R = len(items)
    return [
        [
            (b, slice(None) if len(rows) == R else np.array(rows, dtype=np.int64))
            for b, rows in per_item.values()
        ]
        for per_item in found
    ]


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
        its wanted item (``out``: the same for every hypothesis): :meth:`decision_rows` of one row."""
        return self.decision_rows([items], cell, held, action)[0]

    def decision_rows(
        self, items: Sequence[Sequence[SharedItemBelief]], cell: int, held: int, action: int
    ) -> FloatArray:
        """``(R, D, P)`` :meth:`decision_likelihood` for each of ``R`` rows' items: each
        distinct item belief's row is kept on its :class:`SharedItemBelief`, those not yet worked out
        in one batched product (:meth:`wanted_likelihood`)."""
        K = self.model.n_items
        found = holders(items)
        key = (cell, held, action)
        missing = [(k, b) for k in range(K) for b, _ in found[k] if (k, *key) not in b.decisions]
        if missing:
            ks = np.array([k for k, _ in missing], dtype=np.int64)
            rows = self.wanted_likelihood(np.stack([b.values for _, b in missing]), ks, cell, held, action)
            for (k, b), row in zip(missing, rows, strict=True):
                b.decisions[(k, cell, held, action)] = row
        out = np.empty((len(items), K + 1, len(items[0][0].values)))
        for k in range(K):
            for b, held_by in found[k]:
                out[held_by, k] = b.decisions[(k, cell, held, action)]
        q = self.policy.q[K, cell, self.policy.relative(held)[K], 0]  # (A,) out's
        out[:, K] = choice_likelihood(q, action, self.settings.beta, self.settings.epsilon)
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
        """Every item's hypotheses after the percept (to the true world for ``true_world``):
        :meth:`revise_rows` of one row."""
        return self.revise_rows([items], [truth], [percept])[0]

    def revise_rows(
        self,
        items: Sequence[Sequence[SharedItemBelief]],
        truths: Sequence[tuple[int, ...]],
        percepts: Sequence[Percept],
    ) -> list[tuple[SharedItemBelief, ...]]:
        """Each of ``R`` rows' items after its own percept (its truth for ``true_world``): an
        item's revision by the same percept of it is kept on its :class:`SharedItemBelief`, and those
        not yet worked out, whatever row holds them, are revised in one pass per cell
        (:meth:`FactoredBeliefs.revise_items`)."""
        if self.true_world:
            return [
                tuple(
                    SharedItemBelief(b)
                    for b in np.einsum("kij,knj->kni", self.beliefs.true_world(t, p), stacked(row))
                )
                for row, t, p in zip(items, truths, percepts, strict=True)
            ]
        K = self.model.n_items
        by_percept: dict[Percept, list[tuple[int, int, int, bool]]] = {}
        for p in percepts:  # (the rows of one branch mostly perceive alike)
            if p not in by_percept:
                by_percept[p] = [(k, p.cell, p.seen[k], k in p.lost) for k in range(K)]
        keys = [by_percept[p] for p in percepts]
        missing: dict[tuple[int, tuple[int, int, int, bool]], SharedItemBelief] = {}
        for row, row_keys in zip(items, keys, strict=True):
            for belief, key in zip(row, row_keys, strict=True):
                if key not in belief.successors:
                    missing[(id(belief), key)] = belief
        for cell in {key[1] for _, key in missing}:
            todo = [(belief, key) for (_, key), belief in missing.items() if key[1] == cell]
            new = self.beliefs.revise_items(
                stacked([belief for belief, _ in todo]),
                cell,
                np.array([key[2] for _, key in todo], dtype=np.int64),
                np.array([key[3] for _, key in todo], dtype=bool),
                np.array([key[0] for _, key in todo], dtype=np.int64),
                predict=self.settings.belief_update == "predict",
            )
            for (belief, key), values in zip(todo, new, strict=True):
                belief.successors[key] = SharedItemBelief(values)
        return [
            tuple(belief.successors[key] for belief, key in zip(row, row_keys, strict=True))
            for row, row_keys in zip(items, keys, strict=True)
        ]

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

    def intention(
        self, alpha: FloatArray, weights: FloatArray, items: Sequence[SharedItemBelief]
    ) -> tuple[int | None, int | None, float]:
        """The likeliest (wanted item, where the person believes it is, probability) of a
        posterior ``alpha`` ``(D,)``, ``weights`` ``(D, K, P)`` (:func:`factored_intention`)."""
        own = np.stack([i.own for i in items])  # (K, P, L)
        return factored_intention(alpha, (weights.transpose(1, 0, 2) @ own).transpose(1, 0, 2))

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
