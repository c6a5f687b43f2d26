"""Graded beliefs as a person model (:mod:`brain.model.person.personinterface`): each person holds
a graded belief of their own and plans with it (:mod:`brain.model.graded`);
``ModelSettings.belief_model = "graded"``; online and smoothed."""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass
from typing import overload

import numpy as np

from protocol import Scene

from ...settings import ModelSettings
from ..answers import said_over
from ..arrays import FloatArray
from ..belief import BeliefModel
from ..desires import Desires
from ..estimates import Estimate, estimate, reread
from ..graded import (
    InitialBeliefs,
    drift,
    expected_joint,
    qmdp_likelihood,
    unnormalised_update,
    update_beliefs,
)
from ..inference import hazard_matrix, log_of, switch_probability, switched
from ..lookahead import cached_lookahead
from ..mixture import Beliefs, Mixture, certain, mixture_of, revised
from ..modes import ModeColumns, ModeRates, ModeStep, joint_likelihood, joint_prior, mode_back, mode_step
from ..planner import PlanPolicy, cached_policy
from ..revisions import SharedRevisions
from ..world import value_of
from .personinterface import StepRecord
from .remembered import Remembered


class GradedModel:
    """Graded beliefs (:mod:`brain.model.graded`): the posterior is over ``G`` hypotheses of
    the person's initial belief and ``D`` preferences; each hypothesis's belief follows the
    person's percepts. ``true_world``: the observer assumes people know the true world."""

    exact = True

    def __init__(self, scene: Scene, settings: ModelSettings, true_world: bool) -> None:
        self.policy: PlanPolicy = cached_policy(scene, settings)
        self.model = self.policy.model
        self.desires = Desires(self.policy.utilities)
        self.settings = settings
        self.beliefs = BeliefModel(self.model, settings.r, settings.delta)
        self.true_world = true_world
        self.hypotheses = InitialBeliefs(self.model, settings)
        self.initial = self.hypotheses.beliefs
        self.start: Beliefs = mixture_of(self.initial) or self.initial
        """The hypotheses' initial beliefs as filters hold them: a :class:`Mixture` of the
        point beliefs of the worlds they give mass to (:mod:`brain.model.mixture`), or the
        ``(G, W)`` array where those are as many as the hypotheses."""
        self.place_of = (
            self.model.place[:, :, None] == np.arange(self.model.n_locations)[None, None, :]
        ).astype(np.float64)
        """``(W, K, L)`` one where world ``w`` puts item ``k`` at location ``l``."""
        self.rest_of = (
            (self.model.worlds[:, :, None] == value_of(np.arange(self.model.n_locations))[None, None, :])
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
        errand = settings.errand_per_s if bool(self.model.outside.any()) else 0.0  # none with no outside
        modes = errand > 0 or settings.carry_per_s > 0
        self.rates = (
            ModeRates(errand, settings.carry_per_s, settings.resume_per_s, self.model.n_items)
            if modes
            else None
        )
        """The modes' rates (:mod:`brain.model.modes`); ``None``: no modes (none set)."""
        self.columns = ModeColumns.of(self.policy.utilities, settings.epsilon)
        """Where each mode's likelihood comes from."""

    def desire_switch(self, record: StepRecord) -> float:
        """The lasting desire's redraw chance over the pause before ``record``: the record's,
        but one decision's worth after a pause spent outside (:mod:`brain.model.modes`)."""
        return switch_probability(self.settings.hazard, 1.0) if record.away else record.switch

    def mode_step(self, beliefs: Beliefs, record: StepRecord) -> ModeStep:
        """What the joint over the modes takes of ``record`` (:mod:`brain.model.modes`): the
        pause's switches and the step's likelihood in each mode, what they said included."""
        assert self.rates is not None
        action = self._action_likelihood(beliefs, record)
        likelihood = None if action is None else joint_likelihood(action, record.decision, self.columns)  # type: ignore[arg-type]
        if record.said is not None:
            said = said_over(self.desires, record.said)[None, :, None]
            likelihood = said if likelihood is None else likelihood * said
        seconds = record.elapsed * self.settings.decision_seconds
        return ModeStep(
            likelihood, record.decision, self.desire_switch(record), self.rates.transition(seconds)
        )

    def prior(self, truth: tuple[int, ...] | None = None, memory: Remembered | None = None) -> FloatArray:
        """``(G, U)``: the hypotheses' prior weights given the true item values at the person's
        first sight (:meth:`InitialBeliefs.given`; without ``truth``, the grid's own), uniform
        over candidate desires; or, for a person the brain remembers from an earlier day
        (``memory``), what it read of them then (:mod:`brain.memory.priors`)."""
        U = len(self.policy.utilities)
        weights = self.hypotheses.weights if truth is None else self.hypotheses.given(truth)
        desires = np.full(U, 1.0 / U)
        if memory is not None:
            weights = self.hypotheses.remembered(truth, memory.beliefs, self.settings)
            desires = desires if memory.desires is None else memory.desires
        return weights[:, None] * desires[None, :]

    @property
    def shared(self) -> SharedRevisions | None:
        """:attr:`revisions`, unless this model's revision reads the truth (``true_world``), not
        only the percept: then it shares nothing."""
        return None if self.true_world else self.revisions

    def new_filter(self) -> GradedFilter:
        if self.shared is not None:
            return GradedFilter(self, self.shared.initial(self.revision_key, self.start), self.prior())
        return GradedFilter(self, self._fresh_start(), self.prior())

    def _fresh_start(self) -> Beliefs:
        """The initial beliefs for a filter of its own (a mixture is read-only: shared)."""
        return self.start if isinstance(self.start, Mixture) else self.initial.copy()

    def likelihood(self, cell: int, held: int, action: int) -> FloatArray:
        """The point model's ``(W, U)`` likelihood (kept in the record; the graded filter
        computes its own from ``StepRecord.decision``)."""
        return self.policy.action_likelihood(cell, held, action)

    def decision_likelihood(self, beliefs: Beliefs, record: StepRecord) -> FloatArray | None:
        """``(G, U)`` QMDP likelihood of the record's decision, times the person's answer's
        over the desires (``None`` for a percept alone), from ``(G, W)`` beliefs or their
        :class:`Mixture`."""
        action = self._action_likelihood(beliefs, record)
        if record.said is None:
            return action
        said = said_over(self.desires, record.said)[None, :]
        return np.repeat(said, len(beliefs), axis=0) if action is None else action * said

    def _action_likelihood(self, beliefs: Beliefs, record: StepRecord) -> FloatArray | None:
        """``(G, U)`` QMDP likelihood of the record's decision (``None`` for a percept alone)."""
        if record.decision is None:
            return None
        cell, held, action = record.decision
        beta, epsilon = self.settings.beta, self.settings.epsilon
        if self.lookahead is not None:
            rest = (beliefs @ self.rest_of).reshape(len(beliefs), self.model.n_items, self.model.n_locations)
            return self.lookahead.likelihood(rest, cell, held, action, beta, epsilon)
        q = self.policy.q[:, self.policy.state_slice(cell, held), :]
        if isinstance(beliefs, Mixture) and len(beliefs.vectors) == 1:  # every hypothesis alike
            one = qmdp_likelihood(beliefs.vectors, q, action, beta, epsilon)
            return np.repeat(one, len(beliefs), axis=0)
        if isinstance(beliefs, np.ndarray) and _one_world(beliefs):  # truebelief: the one true world
            one = qmdp_likelihood(beliefs[:1], q, action, beta, epsilon)
            return np.repeat(one, len(beliefs), axis=0)
        return qmdp_likelihood(beliefs, q, action, beta, epsilon)

    @overload
    def revise(self, beliefs: FloatArray, record: StepRecord) -> FloatArray: ...

    @overload
    def revise(self, beliefs: Mixture, record: StepRecord) -> Beliefs: ...

    def revise(self, beliefs: Beliefs, record: StepRecord) -> Beliefs:
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

    def _revise(self, beliefs: Beliefs, record: StepRecord) -> Beliefs:
        """Every hypothesis's belief after the record's percept (a mixture stays one, unless a
        hypothesis's percept is impossible: then the dense array, revised by its rule)."""
        if isinstance(beliefs, Mixture):
            mixed = self._revise_mixture(beliefs, record)
            return mixed if mixed is not None else self._revise_dense(beliefs.dense, record)
        return self._revise_dense(beliefs, record)

    def _revise_dense(self, beliefs: FloatArray, record: StepRecord) -> FloatArray:
        """:meth:`_revise` of the ``(G, W)`` array."""
        if self.true_world:  # every belief moves to the one true world (one row of the transition)
            out = np.zeros_like(beliefs)
            out[:, self.beliefs.true_target(record.truth, record.percept)] = beliefs.sum(axis=1)
            return out
        if record.forget > 0:
            model = self.model
            beliefs = drift(beliefs, model.n_items, model.n_values, record.forget) * model.allowed[None, :]
            beliefs = beliefs / beliefs.sum(axis=1, keepdims=True)
        return update_beliefs(beliefs, self.beliefs, record.percept, self.settings.belief_update)

    def _revise_mixture(self, beliefs: Mixture, record: StepRecord) -> Mixture | None:
        """:meth:`_revise` of a mixture: its components revised (:func:`brain.model.mixture.revised`:
        forgetting, the change and the percept are linear; one normalisation after them)."""
        model = self.model
        if self.true_world:
            target = self.beliefs.true_target(record.truth, record.percept)
            return certain(len(beliefs), model.n_worlds, target)

        def step(rows: FloatArray) -> FloatArray:
            if record.forget > 0:
                rows = drift(rows, model.n_items, model.n_values, record.forget) * model.allowed[None, :]
            return unnormalised_update(rows, self.beliefs, record.percept, self.settings.belief_update)

        return revised(beliefs, step)

    def smoothed(self, records: Sequence[StepRecord], online: Sequence[Estimate]) -> list[Estimate]:
        """Forward-backward over ``(g, d)`` (``g`` never changes; ``d`` may switch), then the
        beliefs replayed to read each step's estimate; with errands, over ``(g, u, m)``."""
        if self.rates is not None:
            return self._smoothed_modes(records)
        beliefs, alpha = self._fresh_start(), self.prior(records[0].truth if records else None)
        alphas, steps = [], []
        for record in records:
            likelihood = self.decision_likelihood(beliefs, record)
            alpha, _ = _filter_step(alpha, likelihood, record.switch)
            beliefs = self._revise(beliefs, record)
            alphas.append(alpha)
            steps.append((likelihood, record.switch))
        back = np.ones_like(alpha)
        posteriors = [alphas[-1]] if alphas else []
        for t in range(len(records) - 1, 0, -1):  # the adjoint of _filter_step: L_t, then H_t^T
            likelihood, switch = steps[t]
            weighted = back * likelihood if likelihood is not None else back
            back = weighted @ hazard_matrix(back.shape[1], switch).T if switch > 0 else weighted
            back = back / back.sum()
            joint = alphas[t - 1] * back
            posteriors.append(joint / joint.sum())
        posteriors.reverse()
        beliefs, out = self._fresh_start(), []
        for record, posterior in zip(records, posteriors, strict=True):
            beliefs = self._revise(beliefs, record)
            out.append(self.read(beliefs, posterior, record.truth))
        return out

    def _smoothed_modes(self, records: Sequence[StepRecord]) -> list[Estimate]:
        """:meth:`smoothed` over ``(g, u, m)``: the adjoint of :func:`brain.model.modes.mode_step`."""
        assert self.rates is not None
        beliefs = self._fresh_start()
        joint = joint_prior(self.prior(records[0].truth if records else None), self.rates)
        joints, steps = [], []
        for record in records:
            step = self.mode_step(beliefs, record)
            joint, _ = mode_step(joint, step)
            beliefs = self._revise(beliefs, record)
            joints.append(joint)
            steps.append(step)
        back = np.ones_like(joint)
        posteriors = [joints[-1]] if joints else []
        for t in range(len(records) - 1, 0, -1):
            back = mode_back(back, steps[t])
            both = joints[t - 1] * back
            posteriors.append(both / both.sum())
        posteriors.reverse()
        beliefs, out = self._fresh_start(), []
        for record, posterior in zip(records, posteriors, strict=True):
            beliefs = self._revise(beliefs, record)
            out.append(self.read(beliefs, posterior.sum(axis=-1), record.truth, posterior.sum(axis=(0, 1))))
        return out

    def read(
        self, beliefs: Beliefs, posterior: FloatArray, truth: tuple[int, ...], mode: FloatArray | None = None
    ) -> Estimate:
        """The estimate of ``(G, W)`` beliefs (or their mixture) under a ``(G, U)`` posterior,
        with the hypotheses kept for reading false beliefs (:func:`false_belief_probability`)
        and P(each mode) ``(M,)``, if the model has modes."""
        model = self.model
        marginals = (  # (G, K, L), shared with the other models that hold this very array
            self._marginals(beliefs)
            if self.shared is None
            else self.shared.read(("marginals", *self.revision_key), beliefs, self._marginals)
        )
        base = estimate(model, expected_joint(beliefs, posterior), truth, self.desires)
        graded = dataclasses.replace(base, hypotheses=(posterior.sum(axis=1), marginals), mode=mode)
        return reread(graded, truth, self.settings.false_belief_mass)

    def _marginals(self, beliefs: Beliefs) -> FloatArray:
        """``(G, K, L)`` each item's location under each of ``(G, W)`` beliefs (or their mixture)."""
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


def _filter_step(
    alpha: FloatArray, likelihood: FloatArray | None, switch: float, base: FloatArray | None = None
) -> tuple[FloatArray, float]:
    """``(G, U)`` posterior after a step and the step's evidence: the preference switch of
    the pause before the step (to the remembered desires ``base``, when given), then the
    decision's likelihood (so the decision is judged under the preference held after the pause)."""
    alpha = switched(alpha, switch, base)
    if likelihood is not None:
        alpha = alpha * likelihood
    total = float(alpha.sum())
    return alpha / total, total


@dataclass
class GradedFilter:
    """The graded forward pass of one person: each hypothesis's belief and the posterior."""

    owner: GradedModel
    state: Beliefs
    """``(G, W)`` every hypothesis's belief, or their :class:`Mixture`."""
    posterior: FloatArray
    """``(G, U)``."""
    log_evidence: float = 0.0
    started: bool = False
    """Whether a step was taken: the first sets the prior by the world then."""
    memory: Remembered | None = None
    """What the brain remembers of the person from an earlier day (sets the prior instead)."""
    joint: FloatArray | None = None
    """``(G, U, M)`` with errands (:mod:`brain.model.modes`): the posterior over the modes
    too (``posterior`` is its sum over them); ``None`` without."""

    def __deepcopy__(self, memo: dict[int, object]) -> GradedFilter:
        """A copy for another row of a lapse mixture (:mod:`brain.model.person.lapses`): a posterior
        of its own, the model shared (a deep copy would copy its Q-values) and so is a
        mixture (read-only: revisions make new ones)."""
        state = self.state if isinstance(self.state, Mixture) else self.state.copy()
        joint = None if self.joint is None else self.joint.copy()
        return dataclasses.replace(self, state=state, posterior=self.posterior.copy(), joint=joint)

    @property
    def beliefs(self) -> FloatArray:
        """``(G, W)`` every hypothesis's belief (a mixture's built, read-only)."""
        return self.state.dense if isinstance(self.state, Mixture) else self.state

    def step(self, record: StepRecord) -> None:
        owner = self.owner
        if not self.started:
            self.posterior, self.started = owner.prior(record.truth, self.memory), True
            self.joint = None if owner.rates is None else joint_prior(self.posterior, owner.rates)
        base = None if self.memory is None else self.memory.desires
        if self.joint is not None:
            step = owner.mode_step(self.state, record)
            self.joint, evidence = mode_step(self.joint, step, base)
            self.posterior, judged = self.joint.sum(axis=-1), step.likelihood is not None
        else:
            likelihood = owner.decision_likelihood(self.state, record)
            self.posterior, evidence = _filter_step(self.posterior, likelihood, record.switch, base)
            judged = likelihood is not None
        if judged:
            self.log_evidence += log_of(evidence)
        self.state = self.owner.revise(self.state, record)

    def estimate(self, truth: tuple[int, ...]) -> Estimate:
        mode = None if self.joint is None else self.joint.sum(axis=(0, 1))
        est = self.owner.read(self.state, self.posterior, truth, mode)
        return dataclasses.replace(est, log_evidence=self.log_evidence)
