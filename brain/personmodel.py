"""The two forms of one person's hidden-state model, behind one interface for the tracker.

- :class:`ExactModel`: the joint ``(W, D)`` posterior over believed worlds and preferences
  (the paper's model; online and smoothed).
- :class:`FactoredModel`: per preference, one belief per item (:mod:`brain.factored`), for
  houses whose ``W = V**K`` worlds do not fit; online only.

:func:`person_model` picks one by ``ModelSettings.exact_max_worlds``. Each step is kept as a
small :class:`StepRecord` (the percept, not the ``(W, W)`` transition, which smoothing
rebuilds), so a long episode does not hold a matrix per step.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Protocol

import numpy as np
import numpy.typing as npt

from protocol import Scene

from .belief import BeliefModel, Percept
from .estimates import Estimate, estimate
from .factored import (
    FactoredBeliefs,
    FactoredPolicy,
    cached_factored_policy,
    factored_estimate,
    factored_prior,
    factored_step,
)
from .inference import HmmStep, forward_step, smooth
from .planner import Policy, cached_policy
from .settings import ModelSettings
from .worldmodel import WorldModel, build_world_model

FloatArray = npt.NDArray[np.float64]


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


class PersonModel(Protocol):
    """What the tracker needs of a model."""

    model: WorldModel
    exact: bool

    def prior(self) -> Any: ...

    def likelihood(self, cell: int, held: int, action: int) -> FloatArray: ...

    def step(self, previous: Any, record: StepRecord) -> Any: ...

    def estimate(self, posterior: Any, truth: tuple[int, ...]) -> Estimate: ...

    def smoothed(self, records: Sequence[StepRecord], online: Sequence[Estimate]) -> list[Estimate]: ...


class ExactModel:
    """The joint model; ``true_world``: the observer assumes people know the true world."""

    exact = True

    def __init__(self, scene: Scene, settings: ModelSettings, true_world: bool) -> None:
        self.policy: Policy = cached_policy(scene, settings)
        self.model = self.policy.model
        self.beliefs = BeliefModel(self.model, settings.r, settings.delta)
        self.true_world = true_world

    def prior(self) -> FloatArray:
        W, D = self.model.n_worlds, self.model.n_items + 1
        return np.full((W, D), 1.0 / (W * D))

    def likelihood(self, cell: int, held: int, action: int) -> FloatArray:
        return self.policy.action_likelihood(cell, held, action)

    def hmm_step(self, record: StepRecord) -> HmmStep:
        if self.true_world:
            transition = self.beliefs.true_world(record.truth, record.percept)
        else:
            transition = self.beliefs.transition(record.percept)
        return HmmStep(record.tick, transition, record.likelihood, record.switch)

    def step(self, previous: FloatArray, record: StepRecord) -> FloatArray:
        return forward_step(previous, self.hmm_step(record))

    def estimate(self, posterior: FloatArray, truth: tuple[int, ...]) -> Estimate:
        return estimate(self.model, posterior, truth)

    def smoothed(self, records: Sequence[StepRecord], online: Sequence[Estimate]) -> list[Estimate]:
        posteriors = smooth(self.prior(), [self.hmm_step(r) for r in records])
        return [self.estimate(p, r.truth) for p, r in zip(posteriors, records, strict=True)]


class FactoredModel:
    """The factored model (:mod:`brain.factored`); it filters only, so its "smoothed"
    estimates are the online ones."""

    exact = False

    def __init__(self, scene: Scene, settings: ModelSettings, true_world: bool) -> None:
        self.policy: FactoredPolicy = cached_factored_policy(scene, settings)
        self.model = self.policy.model
        self.beliefs = FactoredBeliefs(self.model, settings.r, settings.delta)
        self.true_world = true_world

    def prior(self) -> Any:
        return factored_prior(self.model)

    def likelihood(self, cell: int, held: int, action: int) -> FloatArray:
        return self.policy.action_likelihood(cell, held, action)

    def step(self, previous: Any, record: StepRecord) -> Any:
        if self.true_world:
            transition = self.beliefs.true_world(record.truth, record.percept)
        else:
            transition = self.beliefs.transition(record.percept)
        return factored_step(previous, transition, record.likelihood, record.switch)

    def estimate(self, posterior: Any, truth: tuple[int, ...]) -> Estimate:
        return factored_estimate(self.model, posterior, truth)

    def smoothed(self, records: Sequence[StepRecord], online: Sequence[Estimate]) -> list[Estimate]:
        return list(online)


def person_model(scene: Scene, settings: ModelSettings, *, true_world: bool = False) -> PersonModel:
    """The exact model when its ``W`` worlds are at most ``settings.exact_max_worlds``, else
    the factored one."""
    worlds = build_world_model(scene).n_worlds
    if worlds <= settings.exact_max_worlds:
        return ExactModel(scene, settings, true_world)
    return FactoredModel(scene, settings, true_world)
