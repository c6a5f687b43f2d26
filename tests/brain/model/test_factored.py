"""The factored model: its filter is exact for its own (product-form) model, its per-item
belief update is the paper's for one item, it stays close to the exact model on the paper
map's scenarios, and the tracker switches to it above ``exact_max_worlds``."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scenes import tiny_scene

from brain.model.belief import BeliefModel, percept
from brain.model.factored import FactoredBeliefs, FactoredPosterior, factored_estimate, factored_step
from brain.model.inference import HmmStep, forward_step
from brain.model.world import build_world_model
from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from protocol import EpisodeSpec
from sim2d.engine import Engine
from sim2d.generation import write_house_episode
from sim2d.scenario import load_scenario


def random_posterior(rng: np.random.Generator, D: int, K: int, V: int) -> FactoredPosterior:
    b = rng.random((D, K, V)) + 0.05
    alpha = rng.random(D) + 0.1
    return FactoredPosterior(alpha=alpha / alpha.sum(), beliefs=b / b.sum(axis=2, keepdims=True))


def joint(post: FactoredPosterior) -> np.ndarray:
    """``(V, V, D)`` joint of a two-item factored posterior."""
    return np.einsum("d,di,dj->ijd", post.alpha, post.beliefs[:, 0], post.beliefs[:, 1])


def test_the_factored_filter_is_exact_for_its_product_model() -> None:
    """Two items, no switch: one step equals the exact forward step on the joint whose
    transition is the items' Kronecker product and whose likelihood depends on the wanted
    item only."""
    rng = np.random.default_rng(3)
    D, K, V = 3, 2, 4
    post = random_posterior(rng, D, K, V)
    t = rng.random((K, V, V))
    t /= t.sum(axis=1, keepdims=True)
    lik = rng.random((D, V))
    lik[K] = 0.3  # out: no item
    got = factored_step(post, t, lik, switch=0.0)
    full_t = np.kron(t[0], t[1])  # worlds w = i * V + j
    full_lik = np.stack(
        [np.repeat(lik[0], V), np.tile(lik[1], V), np.full(V * V, lik[2, 0])], axis=1
    )  # (W, D): item 0 for d=0, item 1 for d=1
    want = forward_step(joint(post).reshape(V * V, D), HmmStep(0, full_t, full_lik, 0.0))
    assert np.allclose(joint(got).reshape(V * V, D), want, atol=1e-12), "factored step != exact step"


def test_a_preference_switch_keeps_every_marginal() -> None:
    """With a switch the product form is an approximation, but each preference's item
    marginals (what the estimates read) are the exact mixture's."""
    rng = np.random.default_rng(4)
    D, K, V = 3, 2, 4
    post = random_posterior(rng, D, K, V)
    t = np.broadcast_to(np.eye(V), (K, V, V))
    got = factored_step(post, t, None, switch=0.2)
    want = forward_step(joint(post).reshape(V * V, D), HmmStep(0, np.eye(V * V), None, 0.2)).reshape(V, V, D)
    assert np.allclose(got.alpha, want.sum(axis=(0, 1)), atol=1e-12)
    for d in range(D):
        conditional = want[:, :, d] / want[:, :, d].sum()
        assert np.allclose(got.beliefs[d, 0], conditional.sum(axis=1), atol=1e-12)
        assert np.allclose(got.beliefs[d, 1], conditional.sum(axis=0), atol=1e-12)


def test_one_item_beliefs_are_the_papers_update() -> None:
    """With one item, the per-item update is the exact model's transition."""
    model = build_world_model(tiny_scene())
    for cell in range(model.n_cells):
        for value in range(model.n_values):
            seen = percept(model, cell, (value,), None)
            exact = BeliefModel(model, 8.0, 1e-3).transition(seen)
            factored = FactoredBeliefs(model, 8.0, 1e-3).transition(seen)[0]
            assert np.allclose(exact, factored, atol=1e-12), f"cell {cell}, value {value}"


@pytest.mark.parametrize("scenario", ["paper-1", "paper-2", "paper-3", "paper-auto"])
def test_close_to_the_exact_model_on_the_paper_map(scenario: str) -> None:
    engine = Engine(scenario, robot="observe")
    exact = MindTracker(engine.scene(), ModelSettings(belief_model="point"))
    factored = MindTracker(engine.scene(), ModelSettings(belief_model="point", exact_max_worlds=0))
    assert exact.exact and not factored.exact
    beliefs, preferences = [], []
    state, events = engine.state(), ()
    for _ in range(600):
        exact.observe(state, events)
        factored.observe(state, events)
        for person in exact.people:
            a, b = exact.online(person), factored.online(person)
            if a is not None and b is not None:
                beliefs.extend(0.5 * np.abs(a.beliefs - b.beliefs).sum(axis=1))
                preferences.append(0.5 * np.abs(a.preference - b.preference).sum())
        if engine.done:
            break
        result = engine.step()
        state, events = result.state, result.events
    assert np.mean(beliefs) <= 0.01, f"mean belief TV {np.mean(beliefs):.4f}, expected <= 0.01"
    assert np.mean(preferences) <= 0.05, f"mean preference TV {np.mean(preferences):.4f}, expected <= 0.05"


def test_a_large_house_runs_factored(tmp_path: Path) -> None:
    path = write_house_episode(tmp_path, rooms=10, items=6, seed=2, spec=EpisodeSpec(max_ticks=200))
    engine = Engine(load_scenario(str(path)), robot="observe")
    tracker = MindTracker(engine.scene())
    assert not tracker.exact, f"{tracker.model.n_worlds} worlds should exceed the exact model's limit"
    assert tracker.model.n_worlds == 20**6
    state, events = engine.state(), ()
    for _ in range(200):
        tracker.observe(state, events)
        result = engine.step()
        state, events = result.state, result.events
    for person in tracker.people:
        estimate = tracker.online(person)
        assert estimate is not None
        assert estimate.beliefs.shape == (6, 10)
        assert np.allclose(estimate.beliefs.sum(axis=1), 1.0) and np.isclose(estimate.preference.sum(), 1.0)
    assert len(tracker.smoothed(tracker.people[0])) == len(tracker.tracks[tracker.people[0]].steps)


def test_factored_estimate_reads_marginals() -> None:
    model = build_world_model(tiny_scene())
    D, V = 2, model.n_values
    b = np.zeros((D, 1, V))
    b[0, 0, 0] = 1.0  # wants the ball: believes it rests at A
    b[1, 0, 2] = 1.0  # wants out: believes it rests at B
    est = factored_estimate(model, FactoredPosterior(np.array([0.25, 0.75]), b), truth=(2,))
    assert np.allclose(est.beliefs, [[0.25, 0.75]]) and est.false_beliefs == ()
    assert est.intention == (None, None, 0.75)


@pytest.mark.parametrize("scenario", ["paper-1", "paper-2", "paper-3", "sally-anne"])
def test_graded_factored_is_close_to_the_exact_graded_model(scenario: str) -> None:
    """Graded beliefs per item against the exact graded model, online, on the paper map:
    item beliefs, preferences and false-belief probabilities per person and tick."""
    engine = Engine(scenario, robot="observe")
    exact = MindTracker(
        engine.scene(), ModelSettings(errand_per_s=0.0, carry_per_s=0.0)
    )  # the factored has no errands
    factored = MindTracker(engine.scene(), ModelSettings(exact_max_worlds=0))
    assert type(factored.person_model).__name__ == "GradedFactoredModel"
    beliefs, preferences, false = [], [], []
    state, events = engine.state(), ()
    while True:
        exact.observe(state, events)
        factored.observe(state, events)
        for person in exact.people:
            a, b = exact.online(person), factored.online(person)
            if a is not None and b is not None:
                beliefs.extend(0.5 * np.abs(a.beliefs - b.beliefs).sum(axis=1))
                preferences.append(0.5 * np.abs(a.preference - b.preference).sum())
                false.extend(np.abs(a.false_belief - b.false_belief))
        if engine.done:
            break
        result = engine.step()
        state, events = result.state, result.events
    assert np.mean(beliefs) <= 0.02, f"mean belief TV {np.mean(beliefs):.4f}, expected <= 0.02"
    assert np.mean(preferences) <= 0.05, f"mean preference TV {np.mean(preferences):.4f}, expected <= 0.05"
    assert np.mean(false) <= 0.02, f"mean false-belief difference {np.mean(false):.4f}, expected <= 0.02"
