"""The two forms of one person's hidden-state model, behind one interface for the tracker.

- :class:`ExactModel`: the joint ``(W, D)`` posterior over believed worlds and preferences
  (the paper's model; online and smoothed).
- :class:`FactoredModel`: per preference, one belief per item (:mod:`brain.model.factored`), for
  houses whose ``W = V**K`` worlds do not fit; online only.

:func:`person_model` picks one by ``ModelSettings.exact_max_worlds``. Each step is kept as a
small :class:`StepRecord` (the percept, not the ``(W, W)`` transition, which smoothing
rebuilds), so a long episode does not hold a matrix per step.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from protocol import Scene

from ..settings import ModelSettings
from .arrays import FloatArray
from .belief import BeliefModel, Percept
from .estimates import Estimate, estimate
from .factored import (
    FactoredBeliefs,
    FactoredPolicy,
    FactoredPosterior,
    cached_factored_policy,
    factored_estimate,
    factored_prior,
    factored_step,
)
from .inference import HmmStep, forward_step, smooth
from .planner import Policy, cached_policy
from .world import WorldModel, build_world_model


@dataclass(frozen=True)
class StepRecord:
    """One step of a person's chain, as observed.

    Attributes:
        tick: the engine tick of the step.
        percept: what the person perceives after it.
        truth: the true item values then.
        likelihood: the action likelihood (the model's shape), ``None`` for a percept alone.
        switch: probability that the preference changes at this step.
    """

    tick: int
    percept: Percept
    truth: tuple[int, ...]
    likelihood: FloatArray | None
    switch: float


class PersonFilter(Protocol):
    """One person's online filter in some model's form."""

    def step(self, record: StepRecord) -> None:
        """Take in one step."""

    def estimate(self, truth: tuple[int, ...]) -> Estimate:
        """The current estimate, false beliefs read against ``truth``."""


class PersonModel(Protocol):
    """What the tracker needs of a model."""

    model: WorldModel
    exact: bool

    def new_filter(self) -> PersonFilter:
        """A filter at the prior, for a person first seen."""

    def likelihood(self, cell: int, held: int, action: int) -> FloatArray:
        """The likelihood of ``action`` from ``(cell, held)``, in this model's shape."""

    def smoothed(self, records: Sequence[StepRecord], online: Sequence[Estimate]) -> list[Estimate]:
        """Estimates after each step given all of them."""


class ExactModel:
    """The joint model; ``true_world``: the observer assumes people know the true world."""

    exact = True

    def __init__(self, scene: Scene, settings: ModelSettings, true_world: bool) -> None:
        self.policy: Policy = cached_policy(scene, settings)
        self.model = self.policy.model
        self.beliefs = BeliefModel(self.model, settings.r, settings.delta)
        self.true_world = true_world

    def prior(self) -> FloatArray:
        """``(W, D)`` uniform."""
        W, D = self.model.n_worlds, self.model.n_items + 1
        return np.full((W, D), 1.0 / (W * D))

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
        return HmmStep(record.tick, transition, record.likelihood, record.switch)

    def smoothed(self, records: Sequence[StepRecord], online: Sequence[Estimate]) -> list[Estimate]:
        posteriors = smooth(self.prior(), [self.hmm_step(r) for r in records])
        return [estimate(self.model, p, r.truth) for p, r in zip(posteriors, records, strict=True)]


@dataclass
class ExactFilter:
    """The ``(W, D)`` forward pass of one person."""

    owner: ExactModel
    posterior: FloatArray

    def step(self, record: StepRecord) -> None:
        self.posterior = forward_step(self.posterior, self.owner.hmm_step(record))

    def estimate(self, truth: tuple[int, ...]) -> Estimate:
        return estimate(self.owner.model, self.posterior, truth)


class FactoredModel:
    """The factored model (:mod:`brain.model.factored`); it filters only, so its "smoothed"
    estimates are the online ones."""

    exact = False

    def __init__(self, scene: Scene, settings: ModelSettings, true_world: bool) -> None:
        self.policy: FactoredPolicy = cached_factored_policy(scene, settings)
        self.model = self.policy.model
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

    def smoothed(self, records: Sequence[StepRecord], online: Sequence[Estimate]) -> list[Estimate]:
        return list(online)


@dataclass
class FactoredFilter:
    """The factored forward pass of one person."""

    owner: FactoredModel
    posterior: FactoredPosterior

    def step(self, record: StepRecord) -> None:
        self.posterior = factored_step(
            self.posterior, self.owner.transition(record), record.likelihood, record.switch
        )

    def estimate(self, truth: tuple[int, ...]) -> Estimate:
        return factored_estimate(self.owner.model, self.posterior, truth)


def person_model(scene: Scene, settings: ModelSettings, *, true_world: bool = False) -> PersonModel:
    """The exact model when its ``W`` worlds are at most ``settings.exact_max_worlds``, else
    the factored one."""
    worlds = build_world_model(scene).n_worlds
    if worlds <= settings.exact_max_worlds:
        return ExactModel(scene, settings, true_world)
    return FactoredModel(scene, settings, true_world)
