"""The forms of one person's hidden-state model, behind one interface for the tracker.

- :class:`ExactModel`: the joint ``(W, U)`` posterior over believed worlds and candidate desires
  (the paper's point-belief model; online and smoothed).
- :class:`FactoredModel`: per preference, one belief per item (:mod:`brain.model.factored`), for
  houses whose ``W = V**K`` worlds do not fit; online only.
- :class:`GradedModel`: each person holds a graded belief of their own and plans with it
  (:mod:`brain.model.graded`); ``ModelSettings.belief_model = "graded"``; online and smoothed.

:func:`person_model` picks one by ``belief_model`` (graded by default) and ``exact_max_worlds``.
Each step is kept as a small :class:`StepRecord` (the percept, not the ``(W, W)``
transition, which smoothing rebuilds), so a long episode does not hold a matrix per step.
"""

from __future__ import annotations

import dataclasses
import logging
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from protocol import Scene

from ..settings import ModelSettings
from .arrays import FloatArray
from .belief import BeliefModel, Percept
from .desires import Desires
from .estimates import Estimate, estimate, reread
from .factoredperson import FactoredModel
from .graded import InitialBeliefs, drift, expected_joint, qmdp_likelihood, update_beliefs
from .gradedfactored import GradedFactoredModel
from .inference import HmmStep, forward_step, hazard_matrix, log_of, smooth
from .lookahead import cached_lookahead
from .planner import Policy, cached_policy
from .revisions import SharedRevisions
from .world import WorldModel, build_world_model

log = logging.getLogger(__name__)


@dataclass(frozen=True)
class StepRecord:
    """One step of a person's chain, as observed.

    Attributes:
        tick: the engine tick of the step.
        percept: what the person perceives after it.
        truth: the true item values then.
        likelihood: the action likelihood (the model's shape), ``None`` for a percept alone.
        switch: probability that the preference changes at this step.
        decision: ``(cell, held, action)`` of the decision before the percept (``None`` for a
            percept alone): what a model whose likelihood depends on the person's own belief
            needs.
    """

    tick: int
    percept: Percept
    truth: tuple[int, ...]
    likelihood: FloatArray | None
    switch: float
    decision: tuple[int, int, int] | None = None
    forget: float = 0.0
    """The mass of each item's belief that drifted to uniform since the person's last step
    (``ModelSettings.forget``; graded beliefs only)."""
    rumours: tuple[tuple[int, int, float], ...] = ()
    """``(item, value, probability)``: what someone in the person's region believes of an
    item, and the chance they told it since the last step (``ModelSettings.hearsay``)."""
    elapsed: float = 0.0
    """Decision times since the previous decision (``switch``: the hazard over them)."""


class PersonFilter(Protocol):
    """One person's online filter in some model's form."""

    @property
    def log_evidence(self) -> float:
        """The marginal log-likelihood of the decisions so far (:attr:`Estimate.log_evidence`)."""

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
        return HmmStep(record.tick, transition, record.likelihood, record.switch)

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
        if record.likelihood is not None:
            self.log_evidence += log_of(float((self.posterior * record.likelihood).sum()))
        self.posterior = forward_step(self.posterior, self.owner.hmm_step(record))

    def estimate(self, truth: tuple[int, ...]) -> Estimate:
        est = estimate(self.owner.model, self.posterior, truth, self.owner.desires)
        return dataclasses.replace(est, log_evidence=self.log_evidence)


class GradedModel:
    """Graded beliefs (:mod:`brain.model.graded`): the posterior is over ``G`` hypotheses of
    the person's initial belief and ``D`` preferences; each hypothesis's belief follows the
    person's percepts. ``true_world``: the observer assumes people know the true world."""

    exact = True

    def __init__(self, scene: Scene, settings: ModelSettings, true_world: bool) -> None:
        self.policy: Policy = cached_policy(scene, settings)
        self.model = self.policy.model
        self.desires = Desires(self.policy.utilities)
        self.settings = settings
        self.beliefs = BeliefModel(self.model, settings.r, settings.delta)
        self.true_world = true_world
        self.hypotheses = InitialBeliefs(self.model, settings)
        self.initial = self.hypotheses.beliefs
        self.place_of = (
            self.model.place[:, :, None] == np.arange(self.model.n_locations)[None, None, :]
        ).astype(np.float64)
        """``(W, K, L)`` one where world ``w`` puts item ``k`` at location ``l``."""
        self.rest_of = (
            (self.model.worlds[:, :, None] == 2 * np.arange(self.model.n_locations)[None, None, :])
            .reshape(self.model.n_worlds, -1)
            .astype(np.float64)
        )
        """``(W, K L)`` one where world ``w`` has item ``k`` resting at location ``l``."""
        self.lookahead = cached_lookahead(scene, settings) if settings.person_planner == "belief" else None
        self.revisions: SharedRevisions | None = None
        """Revisions shared with the brain's other models that revise alike (``None``: not
        shared; :mod:`brain.model.revisions`)."""
        self.revision_key: tuple[object, ...] = (scene.name, settings.belief_update)
        """What :meth:`revise` reads besides its arguments: models with equal keys revise alike."""
        self.revision_key += (settings.r, settings.delta, settings.prior_resolution, settings.ignorance)

    def prior(self, truth: tuple[int, ...] | None = None) -> FloatArray:
        """``(G, U)``: the hypotheses' prior weights given the true item values at the person's
        first sight (:meth:`InitialBeliefs.given`; without ``truth``, the grid's own), uniform
        over candidate desires."""
        U = len(self.policy.utilities)
        weights = self.hypotheses.weights if truth is None else self.hypotheses.given(truth)
        return np.repeat(weights[:, None] / U, U, axis=1)

    @property
    def shared(self) -> SharedRevisions | None:
        """:attr:`revisions`, unless this model's revision reads the truth (``true_world``), not
        only the percept: then it shares nothing."""
        return None if self.true_world else self.revisions

    def new_filter(self) -> GradedFilter:
        if self.shared is not None:
            return GradedFilter(self, self.shared.initial(self.revision_key, self.initial), self.prior())
        return GradedFilter(self, self.initial.copy(), self.prior())

    def likelihood(self, cell: int, held: int, action: int) -> FloatArray:
        """The point model's ``(W, U)`` likelihood (kept in the record; the graded filter
        computes its own from ``StepRecord.decision``)."""
        return self.policy.action_likelihood(cell, held, action)

    def decision_likelihood(self, beliefs: FloatArray, record: StepRecord) -> FloatArray | None:
        """``(G, U)`` QMDP likelihood of the record's decision (``None`` for a percept alone)."""
        if record.decision is None:
            return None
        cell, held, action = record.decision
        beta, epsilon = self.settings.beta, self.settings.epsilon
        if self.lookahead is not None:
            rest = (beliefs @ self.rest_of).reshape(len(beliefs), self.model.n_items, self.model.n_locations)
            return self.lookahead.likelihood(rest, cell, held, action, beta, epsilon)
        q = self.policy.q[:, self.policy.state_slice(cell, held), :]
        if _one_world(beliefs):  # truebelief: every hypothesis sits in the one true world
            one = qmdp_likelihood(beliefs[:1], q, action, beta, epsilon)
            return np.repeat(one, len(beliefs), axis=0)
        return qmdp_likelihood(beliefs, q, action, beta, epsilon)

    def revise(self, beliefs: FloatArray, record: StepRecord) -> FloatArray:
        """Every hypothesis's belief after the record's percept (taken from another model
        of the brain that revised the same array alike, when shared)."""
        if self.shared is None:
            return self._revise(beliefs, record)
        return self.shared.revise(
            self.revision_key,
            record.tick,
            record.percept,
            record.forget,
            beliefs,
            lambda before: self._revise(before, record),
        )

    def _revise(self, beliefs: FloatArray, record: StepRecord) -> FloatArray:
        if self.true_world:  # every belief moves to the one true world (one row of the transition)
            out = np.zeros_like(beliefs)
            out[:, self.beliefs.true_target(record.truth, record.percept)] = beliefs.sum(axis=1)
            return out
        if record.forget > 0:
            model = self.model
            beliefs = drift(beliefs, model.n_items, model.n_values, record.forget) * model.allowed[None, :]
            beliefs = beliefs / beliefs.sum(axis=1, keepdims=True)
        return update_beliefs(beliefs, self.beliefs, record.percept, self.settings.belief_update)

    def smoothed(self, records: Sequence[StepRecord], online: Sequence[Estimate]) -> list[Estimate]:
        """Forward-backward over ``(g, d)`` (``g`` never changes; ``d`` may switch), then the
        beliefs replayed to read each step's estimate."""
        beliefs, alpha = self.initial.copy(), self.prior(records[0].truth if records else None)
        alphas, steps = [], []
        for record in records:
            likelihood = self.decision_likelihood(beliefs, record)
            alpha = _filter_step(alpha, likelihood, record.switch)
            beliefs = self._revise(beliefs, record)
            alphas.append(alpha)
            steps.append((likelihood, record.switch))
        back = np.ones_like(alpha)
        posteriors = [alphas[-1]] if alphas else []
        for t in range(len(records) - 1, 0, -1):
            likelihood, switch = steps[t]
            mixed = back @ hazard_matrix(back.shape[1], switch).T if switch > 0 else back
            back = mixed * likelihood if likelihood is not None else mixed
            back /= back.sum()
            joint = alphas[t - 1] * back
            posteriors.append(joint / joint.sum())
        posteriors.reverse()
        beliefs, out = self.initial.copy(), []
        for record, posterior in zip(records, posteriors, strict=True):
            beliefs = self._revise(beliefs, record)
            out.append(self.read(beliefs, posterior, record.truth))
        return out

    def read(self, beliefs: FloatArray, posterior: FloatArray, truth: tuple[int, ...]) -> Estimate:
        """The estimate of ``(G, W)`` beliefs under a ``(G, U)`` posterior, with the
        hypotheses kept for reading false beliefs (:func:`false_belief_probability`)."""
        model = self.model
        marginals = (  # (G, K, L), shared with the other models that hold this very array
            self._marginals(beliefs)
            if self.shared is None
            else self.shared.read(("marginals", *self.revision_key), beliefs, self._marginals)
        )
        base = estimate(model, expected_joint(beliefs, posterior), truth, self.desires)
        graded = dataclasses.replace(base, hypotheses=(posterior.sum(axis=1), marginals))
        return reread(graded, truth, self.settings.false_belief_mass)

    def _marginals(self, beliefs: FloatArray) -> FloatArray:
        """``(G, K, L)`` each item's location under each of ``(G, W)`` beliefs."""
        model = self.model
        flat = beliefs @ self.place_of.reshape(model.n_worlds, -1)
        return flat.reshape(len(beliefs), model.n_items, model.n_locations)


def _one_world(beliefs: FloatArray) -> bool:
    """Whether every row of ``(G, W)`` beliefs is the same and puts all its mass on one world
    (as ``truebelief``'s do after the first step): one row's likelihood is then every row's,
    to the bit (each product has one nonzero term). Cheap to refute on the first and last
    rows, which differ under any observer that keeps graded hypotheses apart."""
    first = beliefs[0]
    return (
        len(beliefs) > 1
        and bool(np.array_equal(first, beliefs[-1]))
        and np.count_nonzero(first) == 1
        and bool((beliefs == first).all())
    )


def _filter_step(alpha: FloatArray, likelihood: FloatArray | None, switch: float) -> FloatArray:
    """``(G, U)`` posterior after a step: the decision's likelihood, then the preference switch."""
    if likelihood is not None:
        alpha = alpha * likelihood
    if switch > 0:
        alpha = alpha @ hazard_matrix(alpha.shape[1], switch)
    return alpha / alpha.sum()


@dataclass
class GradedFilter:
    """The graded forward pass of one person: each hypothesis's belief and the posterior."""

    owner: GradedModel
    beliefs: FloatArray
    """``(G, W)``."""
    posterior: FloatArray
    """``(G, U)``."""
    log_evidence: float = 0.0
    started: bool = False
    """Whether a step was taken: the first sets the prior by the world then."""

    def step(self, record: StepRecord) -> None:
        if not self.started:
            self.posterior, self.started = self.owner.prior(record.truth), True
        likelihood = self.owner.decision_likelihood(self.beliefs, record)
        if likelihood is not None:
            self.log_evidence += log_of(float((self.posterior * likelihood).sum()))
        self.posterior = _filter_step(self.posterior, likelihood, record.switch)
        self.beliefs = self.owner.revise(self.beliefs, record)

    def estimate(self, truth: tuple[int, ...]) -> Estimate:
        est = self.owner.read(self.beliefs, self.posterior, truth)
        return dataclasses.replace(est, log_evidence=self.log_evidence)


def person_model(scene: Scene, settings: ModelSettings, *, true_world: bool = False) -> PersonModel:
    """:func:`base_person_model`, wrapped to allow lapses of attention and hearsay when
    ``settings.miss`` or ``settings.hearsay`` is above 0 (:mod:`brain.model.lapses`)."""
    from .lapses import LapseModel

    base = base_person_model(scene, settings, true_world=true_world)
    lapses = settings.miss > 0 or settings.hearsay > 0
    return LapseModel(base, settings.miss) if lapses and not true_world else base


def base_person_model(scene: Scene, settings: ModelSettings, *, true_world: bool = False) -> PersonModel:
    """The model ``settings.belief_model`` names, graded (the default) or point: exact while
    the scene's ``W`` worlds are at most ``settings.exact_max_worlds``, factored above it
    (:mod:`brain.model.gradedfactored`, :mod:`brain.model.factored`)."""
    worlds = build_world_model(scene).n_worlds
    if worlds > settings.exact_max_worlds:
        if settings.desire_model == "graded" or settings.person_planner == "belief":
            log.warning(
                "scene '%s' has %d worlds (exact_max_worlds = %d): the factored model has "
                "favourite desires and QMDP only (desire_model and person_planner ignored)",
                scene.name,
                worlds,
                settings.exact_max_worlds,
            )
        if settings.belief_model == "graded":
            return GradedFactoredModel(scene, settings, true_world)
        return FactoredModel(scene, settings, true_world)
    if settings.belief_model == "graded":
        return GradedModel(scene, settings, true_world)
    return ExactModel(scene, settings, true_world)
