"""Graded beliefs for houses whose joint over worlds does not fit: the factored model's
assumptions (:mod:`brain.model.factored`) with each person's own belief per item graded.

Each item ``k`` has ``P`` hypotheses of the person's initial belief about it (the grid of
:func:`brain.model.graded.simplex_grid` over its resting locations), each carrying the
person's own belief ``beta[k, p]`` over the item's ``V`` values, revised by Bayes from
their percepts on that item alone (:meth:`FactoredBeliefs.revise`). A person who wants item
``k`` plans with their belief about ``k`` alone, by QMDP over the factored planner's
Q-values of that item's MDP. The robot's posterior is ``alpha[d] * prod_k w[d, k, p_k]``:
given the preference the items' hypotheses are independent, an action is evidence about
the wanted item's hypothesis only, and a preference switch mixes the per-preference
weights, projected back onto per-item ones (assumed-density filtering, as the factored
model does). It filters only. Shapes: ``alpha`` ``(D,)``, ``w`` ``(D, K, P)``, ``beta``
``(K, P, V)``. The error against the exact graded model is measured by ``toyroom bench``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from protocol import Scene

from ..settings import ModelSettings
from .arrays import FloatArray
from .belief import Percept
from .desires import Desires, favourite_utilities
from .estimates import Estimate, reread
from .factored import FactoredBeliefs, FactoredPolicy, cached_factored_policy
from .graded import choice_likelihood, expected_q, initial_points
from .inference import hazard_matrix

if TYPE_CHECKING:
    from .personmodel import StepRecord


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
        points, self.point_weights = initial_points(
            self.model.n_locations, settings.prior_resolution, settings.ignorance
        )  # (P, L), (P,)
        self.initial = np.zeros((len(points), self.model.n_values))
        self.initial[:, 0::2] = points  # resting at l has value 2 l

    def new_filter(self) -> GradedFactoredFilter:
        K, P = self.model.n_items, len(self.initial)
        D = K + 1
        return GradedFactoredFilter(
            owner=self,
            alpha=np.full(D, 1.0 / D),
            weights=np.broadcast_to(self.point_weights, (D, K, P)).copy(),
            beliefs=np.repeat(self.initial[None], K, axis=0),
        )

    def likelihood(self, cell: int, held: int, action: int) -> FloatArray:
        """The point factored model's ``(D, V)`` likelihood (kept in the record)."""
        return self.policy.action_likelihood(cell, held, action)

    def decision_likelihood(self, beliefs: FloatArray, cell: int, held: int, action: int) -> FloatArray:
        """``(D, P)`` the QMDP probability of ``action`` for each preference and hypothesis of
        its wanted item (``out``: the same for every hypothesis)."""
        K = self.model.n_items
        relative = self.policy.relative(held)
        out = np.empty((K + 1, beliefs.shape[1]))
        for d in range(K + 1):
            q = self.policy.q[d, cell, relative[d]]  # (V_d, A)
            if d == K:
                out[d] = choice_likelihood(q[0], action, self.settings.beta, self.settings.epsilon)
                continue
            values = expected_q(beliefs[d], q)  # (P, A) under each hypothesis's belief about d
            out[d] = choice_likelihood(values, action, self.settings.beta, self.settings.epsilon)
        return out

    def revise(self, beliefs: FloatArray, truth: tuple[int, ...], percept: Percept) -> FloatArray:
        """Every item's hypotheses after the percept (to the true world for ``true_world``)."""
        if self.true_world:
            return np.einsum("kij,knj->kni", self.beliefs.true_world(truth, percept), beliefs)
        return self.beliefs.revise(beliefs, percept, predict=self.settings.belief_update == "predict")

    def smoothed(self, records: Sequence[StepRecord], online: Sequence[Estimate]) -> list[Estimate]:
        return list(online)


@dataclass
class GradedFactoredFilter:
    """The graded factored forward pass of one person."""

    owner: GradedFactoredModel
    alpha: FloatArray
    weights: FloatArray
    beliefs: FloatArray
    log_evidence: float = 0.0

    def step(self, record: StepRecord) -> None:
        if record.decision is not None:
            likelihood = self.owner.decision_likelihood(self.beliefs, *record.decision)  # (D, P)
            K = self.owner.model.n_items
            items = np.arange(K)
            wanted = self.weights[items, items] * likelihood[:K]  # (K, P)
            evidence = np.append(wanted.sum(axis=1), likelihood[K].mean())
            weighted = self.alpha * evidence
            self.log_evidence += float(np.log(weighted.sum())) if weighted.sum() > 0 else float("-inf")
            if weighted.sum() > 0:
                self.weights = self.weights.copy()
                self.weights[items, items] = wanted / np.where(
                    evidence[:K, None] > 0, evidence[:K, None], 1.0
                )
                self.alpha = weighted / weighted.sum()
        self.beliefs = self.owner.revise(self.beliefs, record.truth, record.percept)
        switch = record.switch
        D = len(self.alpha)
        if switch > 0 and D > 1:
            h = hazard_matrix(D, switch)
            mixed = self.alpha @ h
            self.weights = np.einsum("e,ed,ekp->dkp", self.alpha, h, self.weights) / mixed[:, None, None]
            self.alpha = mixed / mixed.sum()

    def estimate(self, truth: tuple[int, ...]) -> Estimate:
        model = self.owner.model
        K, L = model.n_items, model.n_locations
        own = self.beliefs.reshape(K, -1, L, 2).sum(axis=3)  # (K, P, L) each hypothesis's own belief
        per_item = np.einsum("dkp,kpl->dkl", self.weights, own)  # (D, K, L)
        beliefs = np.einsum("d,dkl->kl", self.alpha, per_item)
        best: tuple[int | None, int | None, float] = (None, None, float(self.alpha[K]))
        for k in range(K):
            joint = self.alpha[k] * per_item[k, k]
            location = int(np.argmax(joint))
            if joint[location] > best[2]:
                best = (k, location, float(joint[location]))
        weights = np.einsum("d,dkp->kp", self.alpha, self.weights)  # (K, P)
        est = Estimate(
            beliefs=beliefs,
            preference=self.alpha.copy(),
            intention=best,
            false_belief=np.zeros(K),
            hypotheses=(weights, own),
            desire=self.owner.desires.summarise(self.alpha),
            log_evidence=self.log_evidence,
        )
        return reread(est, truth, self.owner.settings.false_belief_mass)
