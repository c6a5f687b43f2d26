"""Every value of the cheap parameters from one pass over a recording.

``beta``, ``epsilon`` and ``hazard`` change neither the planner's Q-values (value iteration
takes a hard max) nor which decisions the tracker reads nor how a person's belief follows
their percepts: they enter only the choice rule and the preference switch. So one pass reads
the decisions and the beliefs behind them, and the forward filter of every grid point runs
on those, vectorised over the points: ``P`` points cost one tracker pass, one belief
revision per step and ``P`` small ``(G, U, A)`` choice rules, instead of ``P`` passes.

The pass uses a tracker whose filters only keep their records (:class:`RecordOnly`); the
replay is :class:`brain.model.person.gradedperson.GradedFilter`'s (graded beliefs, QMDP: the
default, ``truebelief``, ``nocost``) or :class:`~brain.model.person.exactperson.ExactFilter`'s
(``point``) arithmetic on stacked posteriors, checked against them point by point in
``tests/toyroom/fitting/test_replay.py``. Other models (belief-space planning, lapses,
factored scenes, an embodied robot's branches) return ``None``: the caller runs them per
point (:func:`toyroom.fitting.evidence.episode_evidence`).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np

from brain.model.arrays import FloatArray
from brain.model.estimates import Estimate
from brain.model.graded import choice_likelihood, expected_q
from brain.model.person.exactperson import ExactModel
from brain.model.person.gradedperson import GradedModel
from brain.model.person.personinterface import PersonFilter, PersonModel, StepRecord
from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from bridge.recording.trace import Trace
from protocol import Observer, Perception

from .evidence import Evidence

CHEAP = ("beta", "epsilon", "hazard")
"""The parameters one pass serves every value of."""


@dataclass
class RecordOnly:
    """A filter that keeps nothing but the tracker's records (the replay filters them)."""

    first: PersonFilter
    log_evidence: float = 0.0
    cache: dict[tuple[int, ...], Estimate] = dataclasses.field(default_factory=dict)

    def step(self, record: StepRecord) -> None:
        pass

    def estimate(self, truth: tuple[int, ...]) -> Estimate:
        if truth not in self.cache:
            self.cache[truth] = self.first.estimate(truth)
        return self.cache[truth]


class RecordingModel:
    """A person model whose filters only record (see :class:`RecordOnly`)."""

    def __init__(self, base: PersonModel) -> None:
        self.base = base
        self.model = base.model
        self.exact = base.exact

    def new_filter(self) -> RecordOnly:
        return RecordOnly(self.base.new_filter())

    def likelihood(self, cell: int, held: int, action: int) -> FloatArray:
        return self.base.likelihood(cell, held, action)

    def smoothed(self, records: Sequence[StepRecord], online: Sequence[Estimate]) -> list[Estimate]:
        return list(online)


def replayable(settings: ModelSettings, model: PersonModel) -> bool:
    """Whether :func:`evidence_at_points` can serve this model."""
    one_branch = settings.perception == Perception.OMNISCIENT
    if isinstance(model, GradedModel):
        return one_branch and model.lookahead is None
    return one_branch and isinstance(model, ExactModel)


def evidence_at_points(
    trace: Trace, settings: ModelSettings, observer: Observer, points: Sequence[Mapping[str, float]]
) -> list[Evidence] | None:
    """The evidence of ``trace`` at each of ``points`` (values of :data:`CHEAP` only, over
    ``settings``), or ``None`` when the model is not replayable."""
    tracker = MindTracker(trace.info.scene, settings, observer=observer)
    base = tracker.person_model
    if not replayable(settings, base) or any(set(p) - set(CHEAP) for p in points):
        return None
    tracker.person_model = RecordingModel(base)
    for state, events in trace:
        tracker.observe(state, events)
    values = {name: np.array([float(p.get(name, getattr(settings, name))) for p in points]) for name in CHEAP}
    total, actions = np.zeros(len(points)), 0
    for person in tracker.people:
        records = tracker.tracks[person].chains[0].steps
        if isinstance(base, GradedModel):
            ll, n = _graded(base, records, values)
        else:
            assert isinstance(base, ExactModel)
            ll, n = _exact(base, records, values)
        total, actions = total + ll, actions + n
    return [Evidence(float(ll), actions) for ll in total]


def _switched(alpha: FloatArray, switch: FloatArray) -> FloatArray:
    """``(P, ..., U)`` posteriors after each point's preference redraw (``hazard_matrix``)."""
    U = alpha.shape[-1]
    s = switch.reshape(-1, *([1] * (alpha.ndim - 1)))
    return (1.0 - s) * alpha + s / U * alpha.sum(axis=-1, keepdims=True)


def _switch(hazard: FloatArray, record: StepRecord) -> FloatArray:
    return 1.0 - (1.0 - hazard) ** max(1.0, record.elapsed)


def _log(evidence: FloatArray) -> FloatArray:
    with np.errstate(divide="ignore"):
        return np.where(evidence > 0, np.log(np.where(evidence > 0, evidence, 1.0)), -np.inf)


def _choice(values: FloatArray, action: int, points: Mapping[str, FloatArray]) -> FloatArray:
    """``(P, ...)`` each point's probability of ``action`` from ``(..., A)`` Q-values: one
    softmax per distinct beta, then each point's ``epsilon`` floor."""
    betas, which = np.unique(points["beta"], return_inverse=True)
    shape = (-1, *([1] * values.ndim))
    soft = choice_likelihood(values[None], action, betas.reshape(shape), 0.0)[which]  # (P, ...)
    epsilon = points["epsilon"].reshape(shape[:-1])
    return (1.0 - epsilon) * soft + epsilon / values.shape[-1]


def _graded(
    model: GradedModel, records: Sequence[StepRecord], points: Mapping[str, FloatArray]
) -> tuple[FloatArray, int]:
    beliefs = model.initial.copy()
    alpha = np.repeat(model.prior()[None], len(points["beta"]), axis=0)  # (P, G, U)
    ll, n = np.zeros(len(alpha)), 0
    for record in records:
        if record.decision is not None:
            cell, held, action = record.decision
            q = model.policy.q[:, model.policy.state_slice(cell, held), :]
            likelihood = _choice(expected_q(beliefs, q.transpose(1, 0, 2)), action, points)
            alpha = _switched(alpha, _switch(points["hazard"], record)) * likelihood  # switch first
            total = alpha.sum(axis=(1, 2), keepdims=True)
            ll += _log(total.reshape(-1))
            alpha = alpha / total
            n += 1
        beliefs = model.revise(beliefs, record)
    return ll, n


def _transform(transition: FloatArray, alpha: FloatArray) -> FloatArray:
    """``(P, W, U)``: ``transition @ alpha[p]`` for every point, as one BLAS product."""
    P, W, U = alpha.shape
    flat = transition @ alpha.transpose(1, 0, 2).reshape(W, P * U)
    return flat.reshape(W, P, U).transpose(1, 0, 2)


def _exact(
    model: ExactModel, records: Sequence[StepRecord], points: Mapping[str, FloatArray]
) -> tuple[FloatArray, int]:
    alpha = np.repeat(model.prior()[None], len(points["beta"]), axis=0)  # (P, W, U)
    ll, n = np.zeros(len(alpha)), 0
    for record in records:
        weighted = alpha
        if record.decision is not None:  # the switch of the pause before it, then its likelihood
            alpha = _switched(alpha, _switch(points["hazard"], record))
            cell, held, action = record.decision
            q = model.policy.q[:, model.policy.state_slice(cell, held), :]  # (U, W, A)
            likelihood = _choice(q.transpose(1, 0, 2), action, points)  # (P, W, U)
            weighted = alpha * likelihood
            ll += _log(weighted.sum(axis=(1, 2)))
            n += 1
        transition = model.hmm_step(record).transition
        predicted = _transform(transition, weighted)
        total = predicted.sum(axis=(1, 2), keepdims=True)
        if not (total > 0).all():  # every hypothesis ruled out: the percept (after the switch)
            predicted = np.where(total > 0, predicted, _transform(transition, alpha))
        alpha = predicted / predicted.sum(axis=(1, 2), keepdims=True)
    return ll, n
