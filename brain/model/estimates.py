"""Reading estimates off a ``(W, D)`` posterior: each item's believed location, the
preference, the intention and the probability of a false belief about each item."""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from protocol import is_false_belief

from .arrays import TIE, FloatArray, IntArray, first_max
from .desires import Desires, DesireSummary
from .world import WorldModel, is_held, location_of

OUT = "out"
"""The preference for leaving rather than playing."""


@dataclass(frozen=True)
class Estimate:
    """One person's estimated mind.

    Attributes:
        beliefs: ``(K, L)`` probability that the person believes item ``k`` is at location ``l``.
        preference: ``(D,)`` over the items, then ``out``.
        intention: ``(item index or None for out, location index or None, probability)``.
        false_belief: ``(K,)`` the robot's probability that the person's belief gives each
            item's true location (at the time the estimate was read) less than
            ``ModelSettings.false_belief_mass`` times its likeliest location's
            (:func:`false_belief_probability`).
        hypotheses: for a model whose people hold graded beliefs, the robot's weight of each
            hypothesis ``(G,)`` and the person's belief under it ``(G, K, L)`` (or, per item
            for the factored model, ``(K, P)`` and ``(K, P, L)``); ``None`` when each person
            is certain of one world (the hypotheses are then the worlds).
        desire: the expected utility of each goal, P(one goal preferred to another) and the
            most probable ranking (:class:`brain.model.desires.DesireSummary`).
        log_evidence: the marginal log-likelihood (natural log) of the person's decisions so
            far under the model, ``sum_t log P(a_t | a_<t, percepts)``: the filter's
            normalisers, which compare models and fit parameters.
        worlds: ``(W,)`` the person's belief over whole worlds as the robot expects it (so
            "nothing is at that spot" is read exactly, not from marginals); ``None`` for the
            factored model.
        false_table: ``(K, L)`` P(false belief about item ``k`` | it truly rests at ``l``):
            what a :func:`slim` estimate keeps of its hypotheses, so that its false beliefs can
            still be read against any world (:func:`false_belief_probability`, which reads it
            first, made with the same ``mass``); ``None`` until slimmed, but for the graded
            factored model's estimates, made with their hypotheses.
        mode: ``(M,)`` P(each mode) of :class:`brain.model.modes.Mode` (pursuing the lasting
            desire, on an errand); ``None`` for a model without modes.
    """

    beliefs: FloatArray
    preference: FloatArray
    intention: tuple[int | None, int | None, float]
    false_belief: FloatArray
    hypotheses: tuple[FloatArray, FloatArray] | None = None
    desire: DesireSummary | None = None
    worlds: FloatArray | None = None
    log_evidence: float = 0.0
    false_table: FloatArray | None = None
    mode: FloatArray | None = None

    def top_worlds(self, k: int) -> list[tuple[int, float]]:
        """The ``k`` most probable ``(world index, probability)`` of the person's belief
        (empty without the joint: the factored model)."""
        if self.worlds is None:
            return []
        return [(int(w), float(self.worlds[w])) for w in self._world_order[:k]]

    @cached_property
    def _world_order(self) -> IntArray:
        """``(W,)`` the worlds from the most probable, (nearly) equal ones in index order
        (probabilities rounded to 12 places: the order does not hang on rounding). Sorted once
        per estimate: the ``mind`` message reads the top ones at every tick while it stands."""
        assert self.worlds is not None
        return np.argsort(-np.round(self.worlds, 12), kind="stable")

    @cached_property
    def false_beliefs(self) -> tuple[int, ...]:
        """Item indices whose false belief is more probable than not."""
        return tuple(int(k) for k in np.flatnonzero(self.false_belief > 0.5 + TIE))


def estimate(
    model: WorldModel, posterior: FloatArray, truth: tuple[int, ...], desires: Desires | None = None
) -> Estimate:
    """The estimate of a ``(W, U)`` posterior over worlds and candidate desires (``desires``;
    without it, ``U = D`` and desire ``d`` is "goal ``d`` is the favourite") given the true
    item values. ``preference`` is P(each goal is the most wanted)."""
    summary = None
    if desires is not None:
        summary = desires.summarise(posterior.sum(axis=0))
        posterior = posterior @ desires.wanted  # (W, D)
    L, K = model.n_locations, model.n_items
    worlds_p = posterior.sum(axis=1)
    beliefs = np.zeros((K, L))
    for k in range(K):
        beliefs[k] = np.bincount(model.place[:, k], weights=worlds_p, minlength=L)
    preference = posterior.sum(axis=0)
    best: tuple[int | None, int | None, float] = (None, None, float(preference[K]))
    for k in range(K):
        joint = np.bincount(model.place[:, k], weights=posterior[:, k], minlength=L)
        location = first_max(joint)
        if joint[location] > best[2] + TIE:  # the first of (nearly) equal ones wins
            best = (k, location, float(joint[location]))
    return Estimate(
        beliefs=beliefs,
        preference=preference,
        intention=best,
        false_belief=point_false_belief(beliefs, truth),
        desire=summary,
        worlds=worlds_p,
    )


def point_false_belief(beliefs: FloatArray, truth: tuple[int, ...]) -> FloatArray:
    """``(K,)`` for people each certain of one world: ``1 - P(believed at the true location)``
    (``beliefs`` is ``(K, L)``; ``truth`` holds item values, :func:`~brain.model.world.value_of`)."""
    true = location_of(np.array(truth, dtype=np.int64))
    return 1.0 - beliefs[np.arange(len(true)), true]


def false_belief_probability(est: Estimate, truth: tuple[int, ...], mass: float) -> FloatArray:
    """``(K,)`` the robot's probability that the person's belief gives each item's true
    location less than ``mass`` times what it gives its likeliest location
    (:func:`protocol.is_false_belief`, the rule the evaluation scores with): a false belief,
    not mere ignorance. With point beliefs this is ``1 - P(believed at the true location)``."""
    if est.false_table is not None:  # (made with the same mass: ModelSettings.false_belief_mass)
        true = location_of(np.array(truth, dtype=np.int64))
        return est.false_table[np.arange(len(true)), true]
    if est.hypotheses is None:
        return point_false_belief(est.beliefs, truth)
    true = location_of(np.array(truth, dtype=np.int64))
    weights, beliefs = est.hypotheses
    if weights.ndim == 2:  # per item (the factored model): (K, P) weights, (K, P, L) beliefs
        at_true = beliefs[np.arange(len(true)), :, true]  # (K, P)
        return (weights * is_false_belief(at_true, beliefs.max(axis=-1), mass)).sum(axis=1)
    at_true = beliefs[:, np.arange(len(true)), true]  # (G, K)
    return weights @ is_false_belief(at_true, beliefs.max(axis=-1), mass)


def reread(est: Estimate, truth: tuple[int, ...], mass: float) -> Estimate:
    """``est`` with its false beliefs read against ``truth`` (the world as it is now)."""
    return dataclasses.replace(est, false_belief=false_belief_probability(est, truth, mass))


def world_text(model: WorldModel, world: int) -> str:
    """A world as text: ``skate@S1;ball@P2`` (``+held``: carried by someone near there)."""
    return ";".join(
        f"{item}@{model.locations[location_of(value)]}{'+held' if is_held(value) else ''}"
        for item, value in zip(model.items, model.worlds[world], strict=True)
    )


def false_table(est: Estimate, mass: float) -> FloatArray | None:
    """``(K, L)`` P(false belief about item ``k`` | it truly rests at ``l``) under ``est``'s
    graded hypotheses (``None`` without them): :func:`false_belief_probability` for every
    world at once."""
    if est.hypotheses is None:
        return None
    weights, beliefs = est.hypotheses
    false = is_false_belief(beliefs, beliefs.max(axis=-1, keepdims=True), mass)
    if weights.ndim == 2:  # per item (the factored model): (K, P) weights, (K, P, L) beliefs
        return np.einsum("kp,kpl->kl", weights, false)
    return np.tensordot(weights, false, axes=1)  # (G,) weights, (G, K, L) beliefs


def slim(est: Estimate, mass: float) -> Estimate:
    """``est`` with its graded hypotheses, ``(G, K, L)`` marginals that are most of an
    estimate's memory, replaced by their :func:`false_table` (``(K, L)``): what a step's
    estimate keeps once a later one has come, its false beliefs still readable against any
    world (``mass``: ``ModelSettings.false_belief_mass``)."""
    if est.hypotheses is None:
        return est
    table = false_table(est, mass) if est.false_table is None else est.false_table
    return dataclasses.replace(est, hypotheses=None, false_table=table)


def average(weights: FloatArray, values: FloatArray) -> FloatArray:
    """``values`` ``(H, ...)`` averaged with ``weights`` ``(H,)``: ``np.tensordot(weights,
    values, axes=1)``, the same product without its bookkeeping (read many times a tick)."""
    return np.dot(weights.reshape(1, -1), values.reshape(len(weights), -1)).reshape(values.shape[1:])


def mix(estimates: Sequence[Estimate], weights: FloatArray) -> Estimate:
    """The estimate of a mixture: ``weights`` ``(H,)`` (summing to one) over branches that
    differ in the true world, each estimate read against its own (so ``false_belief`` is the
    exact mixture). Beliefs, preferences, false beliefs and worlds are averaged; the graded
    hypotheses are pooled with their weights scaled (read against one world, as ``mind.csv``
    reads them against the most probable one), unless every branch has its false-belief table
    (the graded factored model's, read the same): the tables are averaged, and the mixture is
    slim (a ``(K, H P, L)`` pool each step is most of a lapse mixture's time); the intention
    and desire summary are the likeliest branch's; the log-evidence is the mixture's,
    ``log sum_h w_h exp(e_h)`` with each branch's share of the prior."""
    if len(estimates) == 1:
        return estimates[0]
    w = np.asarray(weights, dtype=np.float64)
    best = estimates[first_max(w)]

    def average_of(values: Sequence[FloatArray]) -> FloatArray:
        return average(w, np.stack(values))

    worlds = None if any(e.worlds is None for e in estimates) else average_of([e.worlds for e in estimates])  # type: ignore[misc]
    hypotheses = None
    tables = [e.false_table for e in estimates]
    if all(e.hypotheses is not None for e in estimates) and any(t is None for t in tables):
        parts = [e.hypotheses for e in estimates if e.hypotheses is not None]
        axis = parts[0][0].ndim - 1  # (G,) weights pool on G; per item (K, P) on P
        hypotheses = (
            np.concatenate([h * p[0] for h, p in zip(w, parts, strict=True)], axis=axis),
            np.concatenate([p[1] for p in parts], axis=axis),
        )
    evidence = np.array([e.log_evidence for e in estimates])
    top = evidence.max()
    modes = [e.mode for e in estimates]
    return dataclasses.replace(
        best,
        mode=None if any(m is None for m in modes) else average_of(modes),  # type: ignore[arg-type]
        false_table=None if any(t is None for t in tables) else average_of(tables),  # type: ignore[arg-type]
        beliefs=average_of([e.beliefs for e in estimates]),
        preference=average_of([e.preference for e in estimates]),
        false_belief=average_of([e.false_belief for e in estimates]),
        worlds=worlds,
        hypotheses=hypotheses,
        log_evidence=float(top + np.log(np.exp(evidence - top).mean())) if np.isfinite(top) else float(top),
    )
