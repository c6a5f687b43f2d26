"""Lapses of attention: a person may fail to notice an item in view (``ModelSettings.miss``).

People in the model see every item in view; real people (and ``--minds rich`` simulated
ones) sometimes overlook one, and then act on a belief their percepts no longer explain.
:class:`LapseFilter` wraps any person filter in a small mixture of *rows*, each a copy of
the filter that assumes a different set of items was overlooked: when an item comes into
view at a spot the row's person does not already believe more likely than not (a sight they
would learn from), the row splits in two, "noticed" (weight ``1 - miss``) and "missed"
(weight ``miss``), and the missed row keeps the item out of its percepts for as long as it
stays in view there: its percepts say nothing of the item
(:data:`~brain.model.belief.UNNOTICED`), so the person's belief about it stays as it was,
right or wrong, sure or not (as ``--minds rich`` simulated people's does). Each row's
weight then follows the evidence of the person's decisions, so a person who walks back to
where the item used to be makes the missed row the likely one: a false belief the percepts
alone cannot show. Hearsay (``ModelSettings.hearsay_per_s``) splits rows the same way: when someone
in the person's region believes an item to be where the row's person does not
(``StepRecord.rumours``, from the tracker), a "told" row takes it in as the robot's speech is
taken (weight: the chance it was said since the last step). Rows with the same overlooked
items and (nearly) the same beliefs are merged; the ``LAPSE_ROWS`` heaviest are kept, and
besides them up to ``UNTESTED_ROWS`` lighter ones that behaviour has not yet shown wrong (a
lapse's row is light from birth, and only the person's acting on the belief it left can lift
it). The estimate is the rows' mixture; the log-evidence is the mixture's (the log of the
summed weights, which start at one). Smoothing returns the online estimates (the rows do not
have a backward pass). Rows whose filters are all graded factored are stepped as one array
and their mixture is read only when asked (:mod:`brain.model.person.gradedrows`).
"""

from __future__ import annotations

import copy
import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass
from typing import cast

import numpy as np

from ..arrays import TIE, FloatArray, first_max
from ..belief import UNNOTICED, Percept
from ..estimates import Estimate, mix
from ..world import WorldModel, is_held, location_of
from .gradedfactored import GradedFactoredFilter
from .gradedrows import graded_owner, read_rows, step_rows
from .personinterface import PersonFilter, PersonModel, StepRecord

LAPSE_ROWS = 8
"""The heaviest rows a person's mixture keeps whatever the evidence (:func:`_merged`)."""
UNTESTED_ROWS = 8
"""Rows kept besides those while behaviour has not spoken against them (:func:`_pruned`)."""
UNTESTED_NATS = 3.0
"""A row whose decisions' log-likelihood is this far below the best row's has been shown
wrong by behaviour (a likelihood ratio of about 20) and may be dropped."""
MERGE_TV = 1e-3
"""Rows whose beliefs differ by less than this (total variation, per item) are merged."""


@dataclass
class Row:
    """One hypothesis of which items the person has overlooked."""

    log_weight: float
    filter: PersonFilter
    missed: frozenset[int] = frozenset()
    beliefs: np.ndarray | None = None
    """``(K, L)`` the row's believed locations after its last step."""
    estimate: Estimate | None = None
    """The row's estimate after its last step, read against that step's truth (``None`` for
    rows stepped together: :mod:`brain.model.person.gradedrows`)."""
    table: FloatArray | None = None
    """``(K, L)`` a graded factored row's false-belief table after its last step (read with
    the other rows', :func:`~brain.model.person.gradedrows.read_rows`)."""
    told: tuple[int, int] | None = None
    """``(item, value)`` the row's person is told at this step (hearsay), then ``None``."""
    prior: float = 0.0
    """The log of the prior chance of the row's lapses (the chances it split off with), so
    ``log_weight - prior`` is the log-likelihood of the decisions under the row."""

    @property
    def evidence(self) -> float:
        """The log-likelihood of the person's decisions under the row's lapses."""
        return self.log_weight - self.prior


@dataclass
class LapseFilter:
    """A person's filter as a mixture of rows (see the module docstring)."""

    model: WorldModel
    miss: float
    rows: list[Row]
    last: Percept | None = None
    stepped: tuple[int, ...] | None = None
    """The truth of the last step (the rows' estimates kept then were read against it)."""
    read: tuple[tuple[int, ...], Estimate] | None = None
    """The truth the mixture's estimate was last read against since the last step, and that
    estimate (the tracker reads it right after each step, against the step's truth)."""

    def __deepcopy__(self, memo: dict[int, object]) -> LapseFilter:
        """A copy for another branch of the unseen world (:func:`brain.tracking.track.forked`):
        each row's filter copied (with ``memo``), what is never changed in place shared (the
        model, the rows' beliefs, tables and estimates, the percepts; a deep copy of the
        estimates was most of a fork's time)."""
        rows = [dataclasses.replace(r, filter=copy.deepcopy(r.filter, memo)) for r in self.rows]
        return dataclasses.replace(self, rows=rows)

    @property
    def log_evidence(self) -> float:
        weights = np.array([r.log_weight for r in self.rows])
        top = weights.max()
        return float(top + np.log(np.exp(weights - top).sum()))

    def step(self, record: StepRecord) -> None:
        step_lapses([self], [record])

    def _step_each(self, rows: list[Row], record: StepRecord) -> None:
        """Step ``rows`` (:meth:`_split`'s) one by one, each estimate read against the step's
        truth (filters that cannot be stepped together, :mod:`~brain.model.person.gradedrows`)."""
        for row in rows:
            before = row.filter.log_evidence
            row.filter.step(dataclasses.replace(record, percept=self._as_seen(row, record.percept)))
            row.log_weight += row.filter.log_evidence - before
            row.estimate = row.filter.estimate(record.truth)
            row.beliefs = row.estimate.beliefs

    def _settle(self, rows: list[Row], record: StepRecord) -> None:
        """Keep ``rows`` after their step, merged and pruned (:func:`_merged`)."""
        self.rows = _merged(rows)
        self.last = record.percept
        self.stepped, self.read = record.truth, None

    def _split(self, record: StepRecord) -> list[Row]:
        """The rows before the step: each row, the "missed" row it splits off for the items
        it may overlook (:meth:`_surprises`), and its "told" rows (:meth:`_told`)."""
        rows: list[Row] = []
        for row in self.rows:
            if row.beliefs is None:  # the person's prior, before their first percept
                row.beliefs = row.filter.estimate(record.truth).beliefs
            missed = frozenset(
                k for k in row.missed if self.last is not None and record.percept.seen[k] == self.last.seen[k]
            )
            split = self._surprises(row, record.percept) if self.miss > 0 else []
            if split:
                chance = float(np.log(self.miss))
                lost = Row(
                    row.log_weight + chance,
                    copy.deepcopy(row.filter),
                    missed | frozenset(split),
                    row.beliefs,
                    prior=row.prior + chance,
                )
                rows.append(lost)
                row.log_weight += float(np.log1p(-self.miss))
                row.prior += float(np.log1p(-self.miss))
            row.missed = missed
            rows.append(row)
            rows.extend(self._told(row, record))
        return rows

    def _surprises(self, row: Row, p: Percept) -> list[int]:
        """Items just come into view (or moved in view), resting at a spot the row's person
        does not already believe more likely than not: every sight they would learn from.
        Overlooking one leaves them believing what they did (:meth:`_as_seen`): a false
        belief when they were sure of another spot, ignorance when they had no idea, and a
        belief the robot never saw form (a person who knew where things were before the
        episode) is among the row's hypotheses either way."""
        out = []
        assert row.beliefs is not None
        for k, value in enumerate(p.seen):
            if value < 0 or is_held(value) or k in row.missed:
                continue
            if self.last is not None and self.last.seen[k] == value:
                continue
            if row.beliefs[k, location_of(value)] < 0.5 - TIE:  # (an even chance, to rounding, is not less)
                out.append(k)
        return out

    def _told(self, row: Row, record: StepRecord) -> list[Row]:
        """A "told" row for each rumour the row's person does not already believe."""
        out = []
        assert row.beliefs is not None
        for k, value, chance in record.rumours:
            if chance <= 0 or first_max(row.beliefs[k]) == location_of(value):
                continue
            told_row = Row(
                row.log_weight + float(np.log(chance)),
                copy.deepcopy(row.filter),
                row.missed,
                row.beliefs,
                prior=row.prior + float(np.log(chance)),
            )
            told_row.told = (k, value)
            row.log_weight += float(np.log1p(-chance))
            row.prior += float(np.log1p(-chance))
            out.append(told_row)
        return out

    def _as_seen(self, row: Row, p: Percept) -> Percept:
        """``p`` with each overlooked item :data:`~brain.model.belief.UNNOTICED`: the percept
        says nothing about it, so the row's person believes of it what they did."""
        seen = list(p.seen)
        for k in row.missed:
            seen[k] = UNNOTICED
        if row.told is not None:  # hearsay: taken in as speech is
            seen[row.told[0]] = row.told[1]
            row.told = None
        return Percept(cell=p.cell, seen=tuple(seen), lost=p.lost)

    def estimate(self, truth: tuple[int, ...]) -> Estimate:
        if self.read is not None and self.read[0] == truth:
            return self.read[1]
        est = dataclasses.replace(self._mixture(truth), log_evidence=self.log_evidence)
        self.read = (truth, est)
        return est

    def _mixture(self, truth: tuple[int, ...]) -> Estimate:
        """The rows' mixture read against ``truth``: the rows' graded factored posteriors read
        together (:func:`~brain.model.person.gradedrows.read_rows`), or each row's estimate
        (kept from the step when read against its truth) mixed."""
        rows = self.rows
        kept = [r.estimate if r.estimate is not None and self.stepped == truth else None for r in rows]
        if len(rows) == 1:
            return kept[0] or rows[0].filter.estimate(truth)
        weights = np.array([r.log_weight for r in rows])
        weights = np.exp(weights - weights.max())
        weights /= weights.sum()
        owner = graded_owner([r.filter for r in rows])
        if owner is not None and all(r.table is not None and r.beliefs is not None for r in rows):
            tables = np.stack([cast(FloatArray, r.table) for r in rows])
            beliefs = np.stack([cast(FloatArray, r.beliefs) for r in rows])
            filters = [cast(GradedFactoredFilter, r.filter) for r in rows]
            return read_rows(owner, filters, beliefs, tables, weights, truth)
        return mix([e or r.filter.estimate(truth) for e, r in zip(kept, rows, strict=True)], weights)


def step_lapses(filters: Sequence[LapseFilter], records: Sequence[StepRecord]) -> None:
    """One step of each lapse mixture of ``filters`` by its record of ``records`` (a person's
    mixtures in the branches of the unseen world: one decision, each branch its own percept
    and truth). Where every row of them all is graded factored and the records share their
    decision, pause and answer, the rows are stepped as one (:func:`~brain.model.person.
    gradedrows.step_rows`) and their estimates read only when asked; else row by row."""
    parts = [f._split(record) for f, record in zip(filters, records, strict=True)]
    rows = [row for part in parts for row in part]
    owner = graded_owner([row.filter for row in rows])
    first = records[0]
    shared = all(
        r.decision == first.decision
        and r.switch == first.switch
        and (
            r.said is first.said
            or (r.said is not None and first.said is not None and np.array_equal(r.said, first.said))
        )
        for r in records
    )
    if owner is None or not shared:
        for f, part, record in zip(filters, parts, records, strict=True):
            f._step_each(part, record)
    else:
        evidence = [row.filter.log_evidence for row in rows]
        percepts, truths = [], []
        for f, part, record in zip(filters, parts, records, strict=True):
            percepts += [f._as_seen(row, record.percept) for row in part]
            truths += [record.truth] * len(part)
        graded = [cast(GradedFactoredFilter, row.filter) for row in rows]
        beliefs, tables = step_rows(owner, graded, first, percepts, truths)
        for r, row in enumerate(rows):
            row.log_weight += row.filter.log_evidence - evidence[r]
            row.beliefs, row.table, row.estimate = beliefs[r], tables[r], None
    for f, part, record in zip(filters, parts, records, strict=True):
        f._settle(part, record)


def _merged(rows: list[Row]) -> list[Row]:
    """Rows with the same overlooked items and (nearly) the same beliefs merged (their
    weights and priors summed, the heavier filter kept), heaviest first, then
    :func:`_pruned`."""
    kept: list[Row] = []
    for row in sorted(rows, key=lambda r: -r.log_weight):
        twin = next(
            (
                k
                for k in kept
                if k.missed == row.missed
                and k.beliefs is not None
                and row.beliefs is not None
                and 0.5 * np.abs(k.beliefs - row.beliefs).sum(axis=1).max() < MERGE_TV
            ),
            None,
        )
        if twin is None:
            kept.append(row)
        else:
            twin.log_weight = float(np.logaddexp(twin.log_weight, row.log_weight))
            twin.prior = float(np.logaddexp(twin.prior, row.prior))
    return _pruned(kept)


def _pruned(rows: list[Row]) -> list[Row]:
    """The :data:`LAPSE_ROWS` heaviest of ``rows`` (heaviest first), and up to
    :data:`UNTESTED_ROWS` more, heaviest first, of those behaviour has not yet shown wrong:
    whose decisions' log-likelihood is within :data:`UNTESTED_NATS` of the best row's. A lapse
    starts light (its prior chance) and its row is as likely as the others until the person
    acts on the belief it left (walks to where the item was): dropping it on its weight alone
    would lose it before behaviour could show it."""
    if len(rows) <= LAPSE_ROWS:
        return rows
    best = max(r.evidence for r in rows)
    untested = [r for r in rows[LAPSE_ROWS:] if r.evidence >= best - UNTESTED_NATS]
    return rows[:LAPSE_ROWS] + untested[:UNTESTED_ROWS]


def lapse_rows(model: object) -> int:
    """The most rows one person's filter under ``model`` keeps: :data:`LAPSE_ROWS` plus
    :data:`UNTESTED_ROWS` for a :class:`LapseModel`, else one."""
    return LAPSE_ROWS + UNTESTED_ROWS if isinstance(model, LapseModel) else 1


class LapseModel:
    """A person model whose filters allow lapses (:class:`LapseFilter`) around ``inner``."""

    def __init__(self, inner: PersonModel, miss: float) -> None:
        self.inner = inner
        self.model = inner.model
        self.exact = inner.exact
        self.miss = miss

    def new_filter(self) -> LapseFilter:
        return LapseFilter(self.model, self.miss, [Row(0.0, self.inner.new_filter())])

    def likelihood(self, cell: int, held: int, action: int) -> np.ndarray:
        return self.inner.likelihood(cell, held, action)

    def smoothed(self, records: Sequence[StepRecord], online: Sequence[Estimate]) -> list[Estimate]:
        return list(online)
