"""What the tracker needs of a person model, whatever its form: the record of one observed
step (:class:`StepRecord`), a person's online filter (:class:`PersonFilter`) and the model
that makes filters and smooths a chain (:class:`PersonModel`). Every form implements these
(:mod:`brain.model.person.exactperson`, :mod:`brain.model.person.gradedperson`,
:mod:`brain.model.person.factoredperson`, :mod:`brain.model.person.gradedfactored`,
:mod:`brain.model.person.lapses`); :func:`brain.model.person.personmodel.person_model` picks one.
Each step is kept as a small :class:`StepRecord` (the percept, not the ``(W, W)``
transition, which smoothing rebuilds), so a long episode does not hold a matrix per step.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Protocol

from ..arrays import FloatArray
from ..belief import Percept
from ..estimates import Estimate
from ..world import WorldModel


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
    """The mass (a probability) of each item's belief that drifted to uniform since the
    person's last step: ``1 - exp(-forget_per_s * seconds)`` (``ModelSettings.forget_per_s``;
    graded beliefs only)."""
    rumours: tuple[tuple[int, int, float], ...] = ()
    """``(item, value, probability)``: what someone in the person's region believes of an
    item, and the chance they told it since the last step (``ModelSettings.hearsay_per_s``)."""
    elapsed: float = 0.0
    """Decision times since the previous decision (``switch``: the hazard over them)."""
    away: bool = False
    """Whether the pause before this decision was spent outside (an errand's absence: the
    lasting desire's hazard counts it as one decision, :mod:`brain.model.modes`)."""
    said: FloatArray | None = None
    """``(D,)`` the likelihood of what the person answered the robot at this step, over their
    favourite goal (:func:`brain.model.answers.answer_likelihood`); ``None``: nothing."""


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
