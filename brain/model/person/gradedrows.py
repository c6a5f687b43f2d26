"""The rows of a lapse mixture (:mod:`brain.model.person.lapses`) whose filters are all graded
factored (:mod:`brain.model.person.gradedfactored`), stepped and read together.

A lapse mixture's rows differ in a few items' beliefs (the items each overlooked or was told
of) and share the others (:class:`~brain.model.person.gradedfactored.SharedItemBelief`); what each
holds of its own is its posterior over the hypotheses, ``alpha`` ``(D,)`` and ``weights``
``(D, K, P)``. Here the ``R`` rows' posteriors are stacked, ``(R, D)`` and ``(R, D, K, P)``,
and a step (the pause's preference switch, then the decision's evidence) is one array
operation over all of them (:func:`switched_rows`, :func:`weighed_rows`); what depends on an
item's beliefs (the decision likelihoods, the beliefs and false-belief cells read) is worked
out once per distinct item belief and handed to the rows holding it (:func:`holders`).

At each step only the rows' beliefs and false-belief tables ``(R, K, L)`` are read (the
beliefs are what the lapses' splits and merges look at, :func:`row_beliefs`); the
mixture's estimate is read when asked (:func:`read_rows`), from those kept with the rows. The
numbers are those of stepping and reading the rows one at a time, to rounding. Pure numpy;
no I/O.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..arrays import FloatArray, first_max
from ..belief import Percept
from ..estimates import Estimate, average
from ..inference import hazard_matrix, log_of
from ..world import location_of
from .gradedfactored import GradedFactoredFilter, GradedFactoredModel, SharedItemBelief, holders, read_out
from .personinterface import StepRecord

Items = Sequence[Sequence[SharedItemBelief]]
"""Each row's ``K`` item beliefs."""


def graded_owner(filters: Sequence[object]) -> GradedFactoredModel | None:
    """The model of ``filters`` when every one is a graded factored filter of that one model
    (the rows can be stepped together), else ``None``."""
    if not filters or not all(isinstance(f, GradedFactoredFilter) for f in filters):
        return None
    owners = {id(f.owner) for f in filters}  # type: ignore[attr-defined]
    return filters[0].owner if len(owners) == 1 else None  # type: ignore[attr-defined]


def switched_rows(alpha: FloatArray, weights: FloatArray, switch: float) -> tuple[FloatArray, FloatArray]:
    """The rows' posteriors ``alpha`` ``(R, D)`` and ``weights`` ``(R, D, K, P)`` after a
    preference switch of chance ``switch`` (each hypothesis's weights under the new preference
    are the old ones mixed by the hazard); ``weights`` (the rows' own) is written over, the
    new weights are a new array (the same arrays when nothing switches)."""
    R, D = alpha.shape
    if switch <= 0 or D <= 1:
        return alpha, weights
    h = hazard_matrix(D, switch)
    mixed = (alpha[:, None, :] @ h)[:, 0]  # (R, D), row by row (as one row's ``alpha @ h``, to the bit)
    weights *= alpha[:, :, None, None]
    joint = h.T @ weights.reshape(R, D, -1)  # (R, D, K P)
    joint /= mixed[:, :, None]
    return mixed / mixed.sum(axis=1, keepdims=True), joint.reshape(weights.shape)


def weighed_rows(
    alpha: FloatArray, weights: FloatArray, likelihood: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """The rows' posteriors ``alpha`` ``(R, D)``, ``weights`` ``(R, D, K, P)`` given evidence
    of ``(R, D, P)`` likelihood per preference and hypothesis of its wanted item (the last
    preference, out, the same for every hypothesis): each preference's wanted item's weights
    are revised, the others' are not evidence. Returns them (``weights`` written in place
    where revised: it must be the rows' own) and each row's ``(R,)`` evidence; a row whose
    evidence is none keeps its posterior."""
    K = weights.shape[2]
    items = np.arange(K)
    wanted = weights[:, items, items] * likelihood[:, :K]  # (R, K, P)
    evidence = np.concatenate([wanted.sum(axis=2), likelihood[:, K].mean(axis=1)[:, None]], axis=1)
    weighted = alpha * evidence  # (R, D)
    totals = weighted.sum(axis=1)
    revised = np.flatnonzero(totals > 0)
    if len(revised):
        given = evidence[revised, :K, None]
        new = wanted[revised] / np.where(given > 0, given, 1.0)  # (n, K, P)
        weights[revised[:, None], items[None, :], items[None, :]] = new
        alpha = alpha.copy()
        alpha[revised] = weighted[revised] / totals[revised, None]
    return alpha, weights, totals


def step_rows(
    owner: GradedFactoredModel,
    filters: Sequence[GradedFactoredFilter],
    record: StepRecord,
    percepts: Sequence[Percept],
    truths: Sequence[tuple[int, ...]],
) -> tuple[FloatArray, FloatArray]:
    """One step of every row's filter: ``record``'s decision, pause and answer, each row with
    its own ``percepts`` (the items it overlooked unnoticed, those it was told of heard) and
    ``truths`` (the rows of several branches of the unseen world stepped together). Their
    posteriors are stacked and stepped as one (:func:`switched_rows`, :func:`weighed_rows`),
    then handed back (each a view of the stacked arrays, which nothing writes in place), and
    every row's items revised (:meth:`GradedFactoredModel.revise_rows`). Returns the rows'
    beliefs and hypotheses' weights after it (:func:`row_beliefs`)."""
    for f, truth in zip(filters, truths, strict=True):
        if not f.started:
            f.weights = np.broadcast_to(owner.prior(truth), f.weights.shape).copy()
            f.started = True
    alpha = np.stack([f.alpha for f in filters])  # (R, D)
    weights = np.stack([f.weights for f in filters])  # (R, D, K, P): the rows' own
    alpha, weights = switched_rows(alpha, weights, record.switch)
    likelihood = None
    if record.decision is not None:
        likelihood = owner.decision_rows([f.items for f in filters], *record.decision)  # (R, D, P)
    if record.said is not None:  # the person's answer: evidence over the preference alone
        said = record.said[None, :, None]
        if likelihood is None:
            likelihood = np.broadcast_to(said, (*alpha.shape, weights.shape[-1]))
        else:
            likelihood = likelihood * said
    if likelihood is not None:
        alpha, weights, totals = weighed_rows(alpha, weights, likelihood)
        if record.decision is not None:
            for f, total in zip(filters, totals, strict=True):
                f.log_evidence += log_of(float(total))
    revised = owner.revise_rows([f.items for f in filters], truths, percepts)
    for r, f in enumerate(filters):
        f.alpha, f.weights, f.items = alpha[r], weights[r], revised[r]
    return row_beliefs(alpha, weights, revised, owner.settings.false_belief_mass)


def row_beliefs(
    alpha: FloatArray, weights: FloatArray, items: Items, mass: float
) -> tuple[FloatArray, FloatArray]:
    """The rows' ``(R, K, L)`` beliefs (where each row's person believes each item is) and
    ``(R, K, L)`` false-belief tables (P(a false belief about item ``k`` | it rests at
    ``l``), ``mass``: ``ModelSettings.false_belief_mass``), from posteriors ``alpha``
    ``(R, D)`` and ``weights`` ``(R, D, K, P)`` over hypotheses whose own beliefs are
    ``items``: each row's hypotheses' ``(K, P)`` weights times each distinct item belief's
    ``(P, 2 L)`` readout (:meth:`SharedItemBelief.readout`), once for the rows holding it."""
    R, D = alpha.shape
    K = weights.shape[2]
    hypotheses = (alpha[:, None, :] @ weights.reshape(R, D, -1)).reshape(R, K, -1)  # (R, K, P)
    L = items[0][0].own.shape[1]
    read = np.empty((R, K, 2 * L))
    found_all = holders(items)
    read_out([belief for found in found_all for belief, _ in found], mass)
    for k, found in enumerate(found_all):
        for belief, rows in found:
            read[rows, k] = hypotheses[rows, k] @ belief.readout(mass)
    return read[..., :L], read[..., L:]


def read_rows(
    owner: GradedFactoredModel,
    filters: Sequence[GradedFactoredFilter],
    beliefs: FloatArray,
    tables: FloatArray,
    weights: FloatArray,
    truth: tuple[int, ...],
) -> Estimate:
    """The estimate of the rows' mixture (:func:`brain.model.estimates.mix` of each row's
    estimate): ``weights`` ``(R,)`` (summing to one) over rows whose beliefs are ``beliefs``
    and false-belief tables ``tables`` (both ``(R, K, L)``, :func:`row_beliefs`), false
    beliefs read against ``truth``. Beliefs, preferences and false-belief tables are
    averaged, the intention and desire summary are the likeliest row's; slim (no
    hypotheses), its log-evidence left to the caller."""
    K = beliefs.shape[1]
    true = location_of(np.array(truth, dtype=np.int64))
    best = filters[first_max(weights)]
    return Estimate(
        beliefs=average(weights, beliefs),
        preference=average(weights, np.stack([f.alpha for f in filters])),
        intention=owner.intention(best.alpha, best.weights, best.items),
        false_belief=average(weights, tables[:, np.arange(K), true]),
        desire=owner.desires.summarise(best.alpha),
        false_table=average(weights, tables),
    )
