"""One person as the tracker follows them: what was last seen of them (:class:`PersonTrack`)
and their chain of steps and estimates in each branch of the unseen world (:class:`Chain`):
forked when the factored world's rows split (:func:`forked`), read now (:func:`read_now`)
and smoothed (:func:`smoothed_chains`)."""

from __future__ import annotations

import copy
from dataclasses import dataclass, field
from typing import cast

from ..model.arrays import FloatArray, IntArray
from ..model.belief import Percept
from ..model.estimates import Estimate, mix, reread, slim
from ..model.person.lapses import LapseFilter, step_lapses
from ..model.person.personinterface import PersonFilter, PersonModel, StepRecord


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


def stepped(filters: list[PersonFilter], records: list[StepRecord]) -> None:
    """One step of a person's filter in each branch of the world, each by its record: lapse
    mixtures all together (:func:`~brain.model.person.lapses.step_lapses`), others one by one."""
    if len(filters) > 1 and all(isinstance(f, LapseFilter) for f in filters):
        step_lapses(cast(list[LapseFilter], filters), records)
        return
    for f, record in zip(filters, records, strict=True):
        f.step(record)


def forked(chains: list[Chain], source: IntArray, keep: object) -> list[Chain]:
    """The chains after a split of the factored world's rows: ``source`` ``(R,)`` names the
    chain each row comes from; a chain named again is copied (its filter deeply, but for
    ``keep``, the person model the filters share, and what it holds; its steps and estimates
    are shared, as they never change)."""
    memo: dict[int, object] = {}
    for held in (keep, getattr(keep, "inner", None)):
        if held is not None:
            memo[id(held)] = held
            memo.update({id(v): v for v in vars(held).values()})
    out, used = [], set()
    for s in (int(i) for i in source):
        chain = chains[s]
        if s in used:
            chain = Chain(
                chain.percept,
                list(chain.steps),
                copy.deepcopy(chain.filter, dict(memo)),
                list(chain.estimates),
            )
        used.add(s)
        out.append(chain)
    return out


def mixed(estimates: list[Estimate], weights: FloatArray, mass: float, pool: bool) -> Estimate:
    """The chains' mixture (:func:`~brain.model.estimates.mix`); unless ``pool``, each slimmed
    first (:func:`~brain.model.estimates.slim`: the factored world's rows keep their false
    beliefs readable, not their pooled hypotheses, a ``(K, R P, L)`` array each read)."""
    return mix(estimates if pool else [slim(e, mass) for e in estimates], weights)


def read_now(
    chains: list[Chain], truths: list[tuple[int, ...]], weights: FloatArray, mass: float, pool: bool = True
) -> Estimate:
    """Each chain's latest estimate, its false beliefs read against its world now
    (``truths``), mixed by ``weights`` (``(R,)``; :func:`mixed`): chains ruled out since the
    person's last step are gone, even when one is left."""
    read = [
        reread(c.estimates[-1] if pool else slim(c.estimates[-1], mass), t, mass)
        for c, t in zip(chains, truths, strict=True)
    ]
    return mix(read, weights)


def smoothed_chains(
    model: PersonModel, chains: list[Chain], weights: FloatArray, mass: float
) -> list[Estimate]:
    """Each chain smoothed (``model``'s smoother) and the chains mixed by ``weights``."""
    if len(chains) == 1:
        return model.smoothed(chains[0].steps, chains[0].estimates)
    per_chain = [model.smoothed(c.steps, c.estimates) for c in chains]
    return [mix([slim(e, mass) for e in step], weights) for step in zip(*per_chain, strict=True)]
