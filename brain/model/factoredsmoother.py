"""Forward-backward for the factored models (point and graded), in their product form.

Both factored filters keep a person's posterior as ``alpha[d] * prod_k w[d, k, x_k]``: for
each preference ``d`` one factor per item over its ``N`` states ``x_k`` (the item's value for
the point model, ``N = V``; the hypothesis of the person's initial belief about it for the
graded one, ``N = P``). The backward message is kept in the same form,

    beta_t(d, x)  ~  c[d] * prod_k u[d, k, x_k],

and one step back from ``t`` to ``t - 1`` is the filter's step (switch, likelihood,
transition) in reverse: each item's states go back through the step's belief transition
(point model only; a graded hypothesis never changes), the action likelihood multiplies the
wanted item's factor (``out``'s is a constant), and the preference switch of the pause
before step ``t`` mixes the per-preference messages (projected back onto per-item factors,
as the forward filter's assumed-density step does). Without a switch the message is exact:
given the preference, an action is evidence about the wanted item alone. The smoothed
posterior is the product of the forward posterior and the message.

Shapes: ``alpha`` and ``c`` ``(D,)``; ``w`` and ``u`` ``(D, K, N)``; a step's likelihood
``(D, N)``; a step's transition ``(K, N, N)`` with ``T[k, i, j] = P(i | j)``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .arrays import FloatArray
from .inference import hazard_matrix


@dataclass(frozen=True)
class ProductPosterior:
    """A factored posterior ``alpha[d] * prod_k weights[d, k, x_k]``: ``(D,)`` and ``(D, K, N)``."""

    alpha: FloatArray
    weights: FloatArray


@dataclass(frozen=True)
class BackwardStep:
    """What the backward pass needs of one step: its ``(D, N)`` action likelihood (``None``
    for a percept alone), its preference switch, and its ``(K, N, N)`` transition (``None``:
    the states do not change)."""

    likelihood: FloatArray | None
    switch: float
    transition: FloatArray | None = None


def _message_step(
    scale: FloatArray, factors: FloatArray, step: BackwardStep
) -> tuple[FloatArray, FloatArray]:
    """The message before ``step`` from the one after it: ``(D,)`` scale, ``(D, K, N)`` factors."""
    D, K, _ = factors.shape
    if step.transition is not None:
        factors = np.einsum("kij,dki->dkj", step.transition, factors)
        sums = factors.sum(axis=2)
        factors = factors / sums[..., None]
        scale = scale * sums.prod(axis=1)
    if step.likelihood is not None:
        items = np.arange(K)
        factors = factors.copy()
        wanted = factors[items, items, :] * step.likelihood[:K]  # (K, N)
        sums = wanted.sum(axis=1)
        factors[items, items, :] = wanted / np.where(sums > 0, sums, 1.0)[:, None]
        scale = scale * np.append(sums, step.likelihood[K].mean())
    if step.switch > 0 and D > 1:  # the switch of the pause before the step: undone last
        mixing = hazard_matrix(D, step.switch) * scale[None, :]  # (d before, d after)
        scale = mixing.sum(axis=1)
        factors = np.einsum("de,ekn->dkn", mixing, factors) / scale[:, None, None]
    total = scale.sum()
    return (scale / total if total > 0 else np.full(D, 1.0 / D)), factors


def combine(forward: ProductPosterior, scale: FloatArray, factors: FloatArray) -> ProductPosterior:
    """The smoothed posterior: the forward one times the backward message."""
    joint = forward.weights * factors
    per_item = joint.sum(axis=2)  # (D, K)
    alpha = forward.alpha * scale * per_item.prod(axis=1)
    total = alpha.sum()
    if not total > 0:  # the message rules everything out (cannot happen above the floor)
        return forward
    return ProductPosterior(alpha / total, joint / np.where(per_item > 0, per_item, 1.0)[..., None])


def smooth_products(
    forward: list[ProductPosterior],
    step_at: Callable[[int], BackwardStep],
    lag: int | None = None,
) -> list[ProductPosterior]:
    """The smoothed posterior after each step, from the forward posteriors after each step
    and ``step_at(t)``, step ``t`` (made on demand: a point model's transitions would not all
    fit in memory): given every step (``lag=None``; the forward list is overwritten), or
    fixed-lag, given the steps up to ``lag`` after it (``O(T lag)``)."""
    if not forward:
        return []
    D, K, N = forward[0].weights.shape
    T = len(forward)
    if lag is None:
        scale, factors = np.full(D, 1.0 / D), np.full((D, K, N), 1.0 / N)
        for t in range(T - 1, 0, -1):
            scale, factors = _message_step(scale, factors, step_at(t))
            forward[t - 1] = combine(forward[t - 1], scale, factors)
        return forward
    smoothed = []
    for t in range(T):
        scale, factors = np.full(D, 1.0 / D), np.full((D, K, N), 1.0 / N)
        for s in range(min(T - 1, t + lag), t, -1):
            scale, factors = _message_step(scale, factors, step_at(s))
        smoothed.append(combine(forward[t], scale, factors))
    return smoothed
