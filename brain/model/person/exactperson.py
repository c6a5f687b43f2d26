"""The point-belief model as a person model (:mod:`brain.model.person.personinterface`): the joint
``(W, U)`` posterior over believed worlds and candidate desires (the paper's model; online
and smoothed)."""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from protocol import Scene

from ...settings import ModelSettings
from ..answers import said_over
from ..arrays import FloatArray
from ..belief import BeliefModel
from ..desires import Desires
from ..estimates import Estimate, estimate
from ..inference import HmmStep, filter_step, log_of, smooth
from ..planner import PlanPolicy, cached_policy
from .personinterface import StepRecord


class ExactModel:
    """The joint model; ``true_world``: the observer assumes people know the true world."""

    exact = True

    def __init__(self, scene: Scene, settings: ModelSettings, true_world: bool) -> None:
        self.policy: PlanPolicy = cached_policy(scene, settings)
        self.model = self.policy.model
        self.desires = Desires(self.policy.utilities)
        self.beliefs = BeliefModel(self.model, settings.r, settings.delta)
        self.true_world = true_world

    def prior(self) -> FloatArray:
        """``(W, U)`` uniform over the worlds the scene allows and the candidate desires."""
        allowed = self.model.allowed.astype(np.float64)
        U = len(self.policy.utilities)
        return np.repeat(allowed[:, None], U, axis=1) / (allowed.sum() * U)

    def new_filter(self) -> ExactFilter:
        return ExactFilter(self, self.prior())

    def likelihood(self, cell: int, held: int, action: int) -> FloatArray:
        return self.policy.action_likelihood(cell, held, action)

    def hmm_step(self, record: StepRecord) -> HmmStep:
        """The step with its ``(W, W)`` belief transition rebuilt from the percept."""
        if self.true_world:
            transition = self.beliefs.true_world(record.truth, record.percept)
        else:
            transition = self.beliefs.transition(record.percept)
        likelihood = record.likelihood
        if record.said is not None:  # the person's answer: evidence over the desires alone
            said = said_over(self.desires, record.said)[None, :]
            likelihood = said if likelihood is None else likelihood * said
            likelihood = np.broadcast_to(likelihood, (self.model.n_worlds, said.shape[1]))
        return HmmStep(record.tick, transition, likelihood, record.switch)

    def smoothed(self, records: Sequence[StepRecord], online: Sequence[Estimate]) -> list[Estimate]:
        posteriors = smooth(self.prior(), [self.hmm_step(r) for r in records])
        return [
            estimate(self.model, p, r.truth, self.desires) for p, r in zip(posteriors, records, strict=True)
        ]


@dataclass
class ExactFilter:
    """The ``(W, U)`` forward pass of one person."""

    owner: ExactModel
    posterior: FloatArray
    log_evidence: float = 0.0

    def step(self, record: StepRecord) -> None:
        self.posterior, evidence = filter_step(self.posterior, self.owner.hmm_step(record))
        if record.likelihood is not None:  # the decision's evidence, after the pause's switch
            self.log_evidence += log_of(evidence)

    def estimate(self, truth: tuple[int, ...]) -> Estimate:
        est = estimate(self.owner.model, self.posterior, truth, self.owner.desires)
        return dataclasses.replace(est, log_evidence=self.log_evidence)
