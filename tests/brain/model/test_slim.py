"""A slimmed estimate (:func:`brain.model.estimates.slim`): what a step's estimate keeps once
a later one has come. Its graded hypotheses give way to a ``(K, L)`` table from which its
false beliefs read exactly as before against every world, in both forms (``(G,)`` hypotheses
of the exact graded model, per-item ``(K, P)`` ones of the factored), and mixed over
branches as before."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from brain.model.estimates import Estimate, false_belief_probability, mix, slim
from brain.model.world import value_of

K, L, MASS = 2, 3, 0.1


def graded(rng: np.random.Generator, per_item: bool) -> Estimate:
    """An estimate with random hypotheses: ``(G,)`` weights and ``(G, K, L)`` beliefs, or
    per item ``(K, P)`` and ``(K, P, L)``; some beliefs sure, some spread."""
    shape = (K, 5, L) if per_item else (6, K, L)
    beliefs = rng.dirichlet(np.full(L, 0.3), size=shape[:-1])
    beliefs[..., 0, :] = np.eye(L)[0]  # a sure belief among them
    weights = rng.dirichlet(np.ones(shape[1]), size=K) if per_item else rng.dirichlet(np.ones(shape[0]))
    return Estimate(beliefs.mean(axis=-2 if per_item else 0), np.ones(K + 1) / (K + 1), (None, None, 0.0),
                    np.zeros(K), hypotheses=(weights, beliefs))  # fmt: skip


def worlds() -> list[tuple[int, ...]]:
    """Every world of resting and carried items (a carried one reads as at its location)."""
    values = [value_of(spot, held) for spot in range(L) for held in (False, True)]
    return list(itertools.product(values, repeat=K))


@pytest.mark.parametrize("per_item", [False, True])
def test_a_slim_estimate_reads_its_false_beliefs_as_before(per_item: bool) -> None:
    rng = np.random.default_rng(7)
    for _ in range(5):
        est = graded(rng, per_item)
        lean = slim(est, MASS)
        assert lean.hypotheses is None and lean.false_table is not None and lean.false_table.shape == (K, L)
        for world in worlds():
            expected = false_belief_probability(est, world, MASS)
            got = false_belief_probability(lean, world, MASS)
            assert got == pytest.approx(expected, abs=1e-12), f"world {world}: {got} against {expected}"


def test_slim_estimates_mix_as_their_full_ones_read() -> None:
    rng = np.random.default_rng(3)
    full = [graded(rng, False) for _ in range(3)]
    weights = np.array([0.5, 0.3, 0.2])
    mixed, lean = mix(full, weights), mix([slim(e, MASS) for e in full], weights)
    for world in worlds():
        assert false_belief_probability(lean, world, MASS) == pytest.approx(
            false_belief_probability(mixed, world, MASS), abs=1e-12
        ), world
    point = Estimate(np.eye(L)[:K], np.ones(K + 1) / (K + 1), (None, None, 0.0), np.zeros(K))
    assert slim(point, MASS) is point, "an estimate without hypotheses has nothing to slim"
