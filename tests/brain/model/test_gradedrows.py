"""A lapse mixture's graded factored rows stepped as one array (:mod:`brain.model.person.gradedrows`)
give the numbers of each row's filter stepped on its own: the posteriors to the bit, the
mixture's estimate to rounding."""

from __future__ import annotations

import copy
import dataclasses

import numpy as np

from brain.model.belief import UNNOTICED, Percept
from brain.model.estimates import mix
from brain.model.person.gradedfactored import GradedFactoredFilter, GradedFactoredModel
from brain.model.person.gradedrows import read_rows, row_beliefs, step_rows
from brain.model.person.personinterface import StepRecord
from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from protocol import RobotMode
from sim2d.engine import Engine

TICKS = 120


def recorded_steps() -> tuple[GradedFactoredModel, list[StepRecord]]:
    """The graded factored model of ``paper-2`` and its first person's steps over the first
    ``TICKS`` ticks."""
    engine = Engine("paper-2", robot=RobotMode.OBSERVE)
    tracker = MindTracker(engine.scene(), ModelSettings(exact_max_worlds=0))
    tracker.observe(engine.state(), ())
    for _ in range(TICKS):
        result = engine.step()
        tracker.observe(result.state, result.events)
    model = tracker.person_model
    assert isinstance(model, GradedFactoredModel)
    return model, tracker.tracks[tracker.people[0]].steps


def overlooking(p: Percept, item: int) -> Percept:
    """``p`` with ``item`` overlooked."""
    seen = list(p.seen)
    seen[item] = UNNOTICED
    return Percept(cell=p.cell, seen=tuple(seen), lost=p.lost)


def test_rows_stepped_together_are_the_rows_stepped_one_by_one() -> None:
    model, records = recorded_steps()
    assert any(r.decision is not None for r in records)
    alone = [model.new_filter() for _ in range(3)]
    together = copy.deepcopy(alone)
    mass = model.settings.false_belief_mass
    for record in records:
        percepts = [record.percept, overlooking(record.percept, 0), overlooking(record.percept, 1)]
        for f, p in zip(alone, percepts, strict=True):
            f.step(dataclasses.replace(record, percept=p))
        beliefs, tables = step_rows(model, together, record, percepts, [record.truth] * 3)
        for a, b in zip(alone, together, strict=True):
            np.testing.assert_array_equal(a.alpha, b.alpha)
            np.testing.assert_array_equal(a.weights, b.weights)
            assert a.log_evidence == b.log_evidence
            assert all(
                x.values is y.values or np.array_equal(x.values, y.values)
                for x, y in zip(a.items, b.items, strict=True)
            )
        weights = np.array([0.5, 0.3, 0.2])
        expected = mix([f.estimate(record.truth) for f in alone], weights)
        got = read_rows(model, together, beliefs, tables, weights, record.truth)
        np.testing.assert_allclose(got.beliefs, expected.beliefs, rtol=0, atol=1e-13)
        np.testing.assert_array_equal(got.preference, expected.preference)
        np.testing.assert_allclose(got.false_belief, expected.false_belief, rtol=0, atol=1e-13)
        np.testing.assert_allclose(got.false_table, expected.false_table, rtol=0, atol=1e-13)
        assert got.intention == expected.intention
    again, _ = row_beliefs(
        np.stack([f.alpha for f in together]),
        np.stack([f.weights for f in together]),
        [f.items for f in together],
        mass,
    )
    np.testing.assert_array_equal(again, beliefs)


def test_the_filters_stepped_together_keep_their_own_arrays() -> None:
    """A row's copy (a lapse splitting off) is not written over by the next step of the rows."""
    model, records = recorded_steps()
    rows: list[GradedFactoredFilter] = [model.new_filter(), model.new_filter()]
    step_rows(model, rows, records[0], [records[0].percept] * 2, [records[0].truth] * 2)
    kept = copy.deepcopy(rows[0])
    before = kept.weights.copy()
    for record in records[1:20]:
        step_rows(model, rows, record, [record.percept] * 2, [record.truth] * 2)
    np.testing.assert_array_equal(kept.weights, before)
