"""Every hypothesis's graded belief as a mixture of a few component beliefs: the same
numbers as the ``(G, W)`` array of :mod:`brain.model.graded`, at a fraction of the cost.

A person's belief revision (:func:`brain.model.graded.update_beliefs`, with forgetting
first, :func:`brain.model.graded.drift`) is a linear map of the belief followed by one
normalisation, and a hypothesis's initial belief (:class:`brain.model.graded.InitialBeliefs`)
is a mixture of the point beliefs of the worlds it gives mass to: every item resting, one
of ``L**K`` worlds (64 on a 512-world house) against ``G`` hypotheses (1331). So
hypothesis ``g``'s belief is, at every step,

    b_g = sum_m weights[g, m] vectors[m]

with ``vectors[m]`` the belief of a person who started certain of world ``m`` (revised as
any belief is, rows normalised) and ``weights[g, m]`` its share in ``g`` (its initial
share times the mass the revisions kept of it, rows normalised). A revision moves the
``M`` components, not the ``G`` hypotheses (``M <= G`` always: the grid holds at least the
certain belief in every world it gives mass to), and what is read off the beliefs (their
product with a ``(W, X)`` matrix) is ``weights @ (vectors @ matrix)``. Every term is
nonnegative, so the sums lose nothing to cancellation: the numbers equal the dense ones to
rounding. Where a revision leaves a hypothesis no mass (a percept none of its worlds
explains: only with ``delta = 0``), the dense update's rule (the hypothesis keeps its belief)
has no mixture form: :func:`revised` then says so and the caller revises the dense array.
Pure numpy.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from .arrays import FloatArray


@dataclass(eq=False)
class Mixture:
    """``G`` beliefs over ``W`` worlds as mixtures of ``M`` components (read-only).

    Attributes:
        weights: ``(G, M)`` each hypothesis's share of each component (rows sum to one).
        vectors: ``(M, W)`` each component's belief (rows sum to one).
    """

    weights: FloatArray
    vectors: FloatArray
    _dense: FloatArray | None = field(default=None, repr=False)

    def __post_init__(self) -> None:
        self.weights.flags.writeable = False
        self.vectors.flags.writeable = False

    def __len__(self) -> int:
        return len(self.weights)

    @property
    def shape(self) -> tuple[int, int]:
        """``(G, W)``, as the dense array's."""
        return (len(self.weights), self.vectors.shape[1])

    def __matmul__(self, matrix: FloatArray) -> FloatArray:
        """``(G, X)`` the beliefs times a ``(W, X)`` matrix: two small products."""
        return self.weights @ (self.vectors @ matrix)

    def joint(self, posterior: FloatArray) -> FloatArray:
        """``(W, U)`` ``sum_g posterior[g, u] b_g``, from a ``(G, U)`` posterior."""
        return self.vectors.T @ (self.weights.T @ posterior)

    @property
    def dense(self) -> FloatArray:
        """``(G, W)`` every hypothesis's belief (built once, read-only)."""
        if self._dense is None:
            dense = self.weights @ self.vectors
            dense.flags.writeable = False
            self._dense = dense
        return self._dense

    def one_world(self) -> bool:
        """Whether every hypothesis holds the same belief, certain of one world (as
        ``truebelief``'s do after the first step)."""
        return len(self.vectors) == 1 and np.count_nonzero(self.vectors[0]) == 1


Beliefs = FloatArray | Mixture
"""Every hypothesis's belief: a ``(G, W)`` array, or the same as a :class:`Mixture`."""


def mixture_of(beliefs: FloatArray) -> Mixture | None:
    """``(G, W)`` beliefs (rows summing to one) as the mixture of the point beliefs of the
    worlds they give mass to; ``None`` when those are as many as the hypotheses (no gain)."""
    support = np.flatnonzero((beliefs > 0).any(axis=0))
    if len(support) >= len(beliefs):
        return None
    vectors = np.zeros((len(support), beliefs.shape[1]))
    vectors[np.arange(len(support)), support] = 1.0
    weights = beliefs[:, support] / beliefs[:, support].sum(axis=1, keepdims=True)
    return Mixture(weights, vectors)


def revised(mixture: Mixture, step: Callable[[FloatArray], FloatArray]) -> Mixture | None:
    """The mixture after a revision whose unnormalised part is the linear map ``step``
    (``(N, W)`` rows in, a new ``(N, W)`` array of the mapped rows out): each component
    mapped and normalised, its shares scaled by the mass it kept (rows renormalised); a
    component that kept no mass is dropped (every share of it is 0). ``None`` when a
    hypothesis keeps no mass (the dense update keeps such a belief as it was: no mixture
    says that)."""
    moved = step(mixture.vectors)  # (M, W)
    kept = moved.sum(axis=1)  # (M,)
    scaled = mixture.weights * kept[None, :]  # (G, M)
    totals = scaled.sum(axis=1)  # (G,)
    if not bool((totals > 0).all()):
        return None
    alive = kept > 0
    if not alive.all():
        moved, kept, scaled = moved[alive], kept[alive], scaled[:, alive]
    moved /= kept[:, None]
    scaled /= totals[:, None]
    return Mixture(scaled, moved)


def certain(n_hypotheses: int, n_worlds: int, world: int) -> Mixture:
    """Every one of ``n_hypotheses`` beliefs certain of ``world``."""
    vectors = np.zeros((1, n_worlds))
    vectors[0, world] = 1.0
    return Mixture(np.ones((n_hypotheses, 1)), vectors)
