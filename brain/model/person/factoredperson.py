"""The factored model as a person model (:mod:`brain.model.person.personinterface`): the
filter of :mod:`brain.model.factored`, and its smoother (:mod:`brain.model.factoredsmoother`)."""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from protocol import Scene

from ...settings import ModelSettings
from ..arrays import FloatArray
from ..desires import Desires, favourite_utilities
from ..estimates import Estimate
from ..factored import (
    FactoredBeliefs,
    FactoredPolicy,
    FactoredPosterior,
    cached_factored_policy,
    factored_estimate,
    factored_filter_step,
    factored_prior,
    factored_step,
)
from ..factoredsmoother import BackwardStep, ProductPosterior, smooth_products
from ..inference import log_of
from .personinterface import StepRecord


class FactoredModel:
    """The factored model (:mod:`brain.model.factored`), smoothed by forward-backward in its
    product form (:mod:`brain.model.factoredsmoother`)."""

    exact = False

    def __init__(self, scene: Scene, settings: ModelSettings, true_world: bool) -> None:
        self.policy: FactoredPolicy = cached_factored_policy(scene, settings)
        self.model = self.policy.model
        self.desires = Desires(favourite_utilities(settings, self.model.n_items))
        self.beliefs = FactoredBeliefs(self.model, settings.r, settings.delta)
        self.true_world = true_world

    def new_filter(self) -> FactoredFilter:
        return FactoredFilter(self, factored_prior(self.model))

    def likelihood(self, cell: int, held: int, action: int) -> FloatArray:
        return self.policy.action_likelihood(cell, held, action)

    def transition(self, record: StepRecord) -> FloatArray:
        """``(K, V, V)`` per-item belief transitions of the step's percept."""
        if self.true_world:
            return self.beliefs.true_world(record.truth, record.percept)
        return self.beliefs.transition(record.percept)

    def likelihood_of(self, record: StepRecord) -> FloatArray | None:
        """``(D, V)`` the record's action likelihood times the person's answer's (``None``:
        neither)."""
        if record.said is None:
            return record.likelihood
        said = record.said[:, None]
        if record.likelihood is None:
            return np.repeat(said, self.model.n_values, axis=1)
        return record.likelihood * said

    def smoothed(
        self, records: Sequence[StepRecord], online: Sequence[Estimate], lag: int | None = None
    ) -> list[Estimate]:
        """Each step's estimate given every step (``lag``: given the next ``lag`` only)."""
        posterior, forward = factored_prior(self.model), []
        for record in records:
            posterior = factored_step(
                posterior, self.transition(record), self.likelihood_of(record), record.switch
            )
            forward.append(ProductPosterior(posterior.alpha, posterior.beliefs))

        def step_at(t: int) -> BackwardStep:
            record = records[t]
            return BackwardStep(self.likelihood_of(record), record.switch, self.transition(record))

        return [
            dataclasses.replace(
                self.read(FactoredPosterior(smoothed.alpha, smoothed.weights), record.truth),
                log_evidence=est.log_evidence,
            )
            for record, smoothed, est in zip(
                records, smooth_products(forward, step_at, lag), online, strict=True
            )
        ]

    def read(self, posterior: FactoredPosterior, truth: tuple[int, ...]) -> Estimate:
        """The estimate of a factored posterior, with its desire summary."""
        est = factored_estimate(self.model, posterior, truth)
        return dataclasses.replace(est, desire=self.desires.summarise(posterior.alpha))


@dataclass
class FactoredFilter:
    """The factored forward pass of one person."""

    owner: FactoredModel
    posterior: FactoredPosterior
    log_evidence: float = 0.0

    def __deepcopy__(self, memo: dict[int, object]) -> FactoredFilter:
        """A copy for another row (the posterior's arrays are never written in place: shared),
        the model shared (a deep copy would copy its Q-values)."""
        return dataclasses.replace(self)

    def step(self, record: StepRecord) -> None:
        self.posterior, evidence = factored_filter_step(
            self.posterior, self.owner.transition(record), self.owner.likelihood_of(record), record.switch
        )
        if record.likelihood is not None:  # the decision's evidence, after the pause's switch
            self.log_evidence += log_of(evidence)

    def estimate(self, truth: tuple[int, ...]) -> Estimate:
        return dataclasses.replace(self.owner.read(self.posterior, truth), log_evidence=self.log_evidence)
