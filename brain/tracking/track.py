"""One person as the tracker follows them: what was last seen of them (:class:`PersonTrack`)
and their chain of steps and estimates in each branch of the unseen world (:class:`Chain`)."""

from __future__ import annotations

from dataclasses import dataclass, field

from ..model.arrays import FloatArray
from ..model.belief import Percept
from ..model.estimates import Estimate, slim
from ..model.personinterface import PersonFilter, StepRecord


@dataclass
class Chain:
    """One person's chain in one branch of the world: its steps and filtered posteriors."""

    percept: Percept | None = None
    steps: list[StepRecord] = field(default_factory=list)
    filter: PersonFilter | None = None
    """The online filter (in the model's form), ``None`` before the first sight."""
    estimates: list[Estimate] = field(default_factory=list)
    """Each step's online estimate, its false beliefs read against the branch's world then
    (only the latest keeps its graded hypotheses: :func:`add`)."""


@dataclass
class PersonTrack:
    """One person: what was last seen of them, their chain in every branch of the world, and
    the estimates reported (the branches' mixture after each step)."""

    agent: str
    cell: int | None = None
    moved_from: int | None = None
    """The cell the person left on their last move."""
    held: int = 0
    last_decision: float | None = None
    last_step: float | None = None
    """The engine time of the person's last step (for forgetting since)."""
    stays: int = 0
    """How many Stay decisions were read in the current pause (since ``last_decision``)."""
    settled: bool = False
    """Whether the person played or left, or has not acted since first seen: no decision is
    due (no wait is read) until they act."""
    said: FloatArray | None = None
    """``(D,)`` what the person answered the robot since their last step (evidence for the
    next one), or ``None``."""
    chains: list[Chain] = field(default_factory=lambda: [Chain()])
    steps: list[StepRecord] = field(default_factory=list)
    """The steps of the likeliest branch (every branch steps at the same ticks)."""
    estimates: list[Estimate] = field(default_factory=list)


def add(estimates: list[Estimate], est: Estimate, mass: float) -> None:
    """Append ``est`` to a history of estimates, slimming the one before
    (:func:`~brain.model.estimates.slim`, ``mass``: ``ModelSettings.false_belief_mass``): the
    hypotheses of every step would hold memory in proportion to the branches of the unseen
    world times the steps (2.4 GiB on a ``house-b`` task episode, embodied, before)."""
    if estimates:
        estimates[-1] = slim(estimates[-1], mass)
    estimates.append(est)
