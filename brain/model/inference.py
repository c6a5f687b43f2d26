"""Inference as a hidden Markov model over z = (believed world, preference).

A step of a person is a decision (an action ``a`` taken from state ``(x, h)``, then the
percept at the new position) or a percept alone (something changed in view, speech):

    alpha_t  ∝  T_t @ (L_t ⊙ (alpha_{t-1} @ H_t))

with ``H_t`` the preference change of the step: with probability ``s_t`` the preference is
redrawn from the prior (uniform, or a person's remembered desires), which may keep it
(Baker, Saxe and Tenenbaum 2009). ``s_t = 0`` for a percept alone; for a decision,
``s_t = 1 - (1 - hazard)^n`` over the ``n`` decision times since the person's previous
decision: the exact compounding of a redraw per decision, ``H^n``, which tends to the prior
and never forces a change (the rule before it put the whole ``1 - (1 - h)^n`` on the *other*
preferences, so a long errand all but certainly flipped a person with two goals). It is applied first, so that
a decision is judged under the preference the person holds after the pause that precedes it;
``L_t[w, d] = P(a_t | x, h, w, d)`` (all ones for a percept alone) and ``T_t`` the belief
transition of the new percept. ``alpha_t`` is over the belief after the step's percept and
the preference that made the step's decision. Forward filtering gives the online estimate;
forward-backward gives the smoothed one. Shapes: ``alpha`` is ``(W, D)``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from .arrays import FloatArray


@dataclass(frozen=True)
class HmmStep:
    """One step of a person's chain.

    Attributes:
        tick: the engine tick it happened at.
        transition: ``(W, W)`` belief transition ``T[i, j] = P(i | j)``.
        likelihood: ``(W, D)`` action likelihood at the previous state, ``None`` for a percept alone.
        switch: probability that the preference is redrawn from the prior in the pause
            before this step (applied before the likelihood; a redraw may keep it).
    """

    tick: int
    transition: FloatArray
    likelihood: FloatArray | None
    switch: float


def hazard_matrix(n_preferences: int, switch: float) -> FloatArray:
    """``(D, D)`` ``H[d_prev, d] = P(d | d_prev)``: kept with ``1 - switch``, else redrawn
    uniformly, which may draw ``d_prev`` again (:func:`switched` applies it, or a redraw from
    remembered desires). Its powers compound exactly: ``H(s)^n = H(1 - (1 - s)^n)``."""
    D = n_preferences
    return (1.0 - switch) * np.eye(D) + switch / D


def log_of(evidence: float) -> float:
    """The log of a step's evidence, ``-inf`` for none (the likelihood's floor keeps it
    positive in practice)."""
    return float(np.log(evidence)) if evidence > 0 else float("-inf")


def switch_probability(hazard: float, elapsed_decisions: float) -> float:
    """The chance of a redraw of the preference over ``elapsed_decisions`` decision times
    (at least one), each with a redraw chance of ``hazard``: ``1 - (1 - hazard)^n``."""
    return 1.0 - (1.0 - hazard) ** max(1.0, elapsed_decisions)


def switched(alpha: FloatArray, switch: float, base: FloatArray | None = None) -> FloatArray:
    """``alpha`` (``(..., D)``) after a redraw of the preference with probability ``switch``
    from ``base`` (``(D,)``: a person's lasting preferences, remembered from earlier days;
    uniform when ``None``), which may keep it."""
    if switch <= 0:
        return alpha
    D = alpha.shape[-1]
    prior = np.full(D, 1.0 / D) if base is None else base
    return (1.0 - switch) * alpha + switch * alpha.sum(axis=-1, keepdims=True) * prior


def filter_step(alpha: FloatArray, step: HmmStep) -> tuple[FloatArray, float]:
    """The filtered ``(W, D)`` posterior after ``step`` and the step's evidence
    ``sum((alpha @ H_t) * L_t)`` (1 for a percept alone): the switch of the pause before
    the step, the decision's likelihood, the belief transition."""
    prior = switched(alpha, step.switch)
    weighted = prior if step.likelihood is None else prior * step.likelihood
    evidence = 1.0 if step.likelihood is None else float(weighted.sum())
    predicted = step.transition @ weighted
    total = predicted.sum()
    if not total > 0:  # every hypothesis ruled out: fall back to the percept (after the switch)
        predicted = step.transition @ prior
        total = predicted.sum()
    return predicted / total, evidence


def forward_step(alpha: FloatArray, step: HmmStep) -> FloatArray:
    """The filtered ``(W, D)`` posterior after ``step``."""
    return filter_step(alpha, step)[0]


def forward(prior: FloatArray, steps: Sequence[HmmStep]) -> list[FloatArray]:
    """Filtered posteriors after each step."""
    out = []
    alpha = prior
    for step in steps:
        alpha = forward_step(alpha, step)
        out.append(alpha)
    return out


def smooth(prior: FloatArray, steps: Sequence[HmmStep]) -> list[FloatArray]:
    """Smoothed posteriors ``P(z_t | all steps)`` after each step (forward-backward)."""
    alphas = forward(prior, steps)
    beta = np.ones_like(prior)
    out: list[FloatArray] = [np.empty(0)] * len(steps)
    for t in range(len(steps) - 1, -1, -1):
        posterior = alphas[t] * beta
        out[t] = posterior / posterior.sum()
        step = steps[t]  # the adjoint of filter_step: T_t^T, then L_t, then H_t^T
        back = step.transition.T @ beta
        if step.likelihood is not None:
            back = back * step.likelihood
        if step.switch > 0:
            back = back @ hazard_matrix(back.shape[1], step.switch).T
        beta = back / back.sum()
    return out
