"""Graded beliefs on hand-built cases: a person's own belief revises by Bayes from what they
see, the paper's r sets how readily they think something moved, and the decisions of a
person who is unsure are read by QMDP."""

from __future__ import annotations

import numpy as np
import pytest

from brain.model.belief import NOT_IN_VIEW, BeliefModel, Percept
from brain.model.graded import (
    believed_possible,
    initial_points,
    prior_beliefs,
    qmdp_likelihood,
    simplex_grid,
    update_beliefs,
)
from brain.model.planner import Move, cached_policy
from brain.model.world import build_world_model
from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from protocol import Observer
from sim2d.engine import Engine

SETTINGS = ModelSettings()


@pytest.fixture(scope="module")
def paper():  # the paper map's world model, with a cell that sees S2 and not P2
    engine = Engine("paper-1")
    model = build_world_model(engine.scene())
    s2, p2 = model.locations.index("S2"), model.locations.index("P2")
    cell = next(c for c in range(model.n_cells) if model.sees[c, s2] and not model.sees[c, p2])
    return engine.scene(), model, s2, p2, cell


def ball_belief(model, beliefs: np.ndarray, item: int) -> np.ndarray:
    """``(L,)`` P(item at each location) under a ``(W,)`` belief."""
    return np.bincount(model.place[:, item], weights=beliefs, minlength=model.n_locations)


def split_prior(model, item: int, a: int, b: int) -> np.ndarray:
    """``(1, W)``: item ``item`` at ``a`` or ``b`` (half each); every other item at ``a`` for sure."""
    values = model.worlds
    at = lambda k, loc: values[:, k] == 2 * loc  # noqa: E731
    others = np.all([at(k, a) for k in range(model.n_items) if k != item], axis=0)
    mass = (at(item, a) | at(item, b)) & others
    return (mass / mass.sum())[None, :]


def test_the_grid_covers_the_simplex() -> None:
    grid = simplex_grid(4, 2)
    assert grid.shape == (10, 4) and np.allclose(grid.sum(axis=1), 1.0)
    assert {tuple(p) for p in simplex_grid(3, 1)} == {(1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)}


def test_prior_beliefs_are_distributions_over_resting_worlds(paper) -> None:
    _, model, *_ = paper
    beliefs, weights = prior_beliefs(model.worlds, model.n_locations, 2)
    assert beliefs.shape == (10**model.n_items, model.n_worlds)
    assert np.allclose(beliefs.sum(axis=1), 1.0) and np.allclose(weights, 1.0 / len(weights))
    held = np.any(model.worlds % 2 == 1, axis=1)
    assert np.all(beliefs[:, held] == 0), "a prior should never have an item held by someone else"


def test_ignorance_adds_the_uniform_belief_with_its_prior_weight() -> None:
    points, weights = initial_points(4, 2, 0.5)
    assert points.shape == (11, 4), f"expected the 10 grid points and the uniform one, got {points.shape}"
    assert np.allclose(points[-1], 0.25) and weights[-1] == 0.5, (points[-1], weights[-1])
    assert np.allclose(weights[:-1], 0.05) and np.isclose(weights.sum(), 1.0)
    on_grid, w = initial_points(2, 2, 0.3)  # (0.5, 0.5) is already a grid point
    assert on_grid.shape == (3, 2) and np.allclose(w, [0.35, 0.3, 0.35]), w
    assert np.allclose(initial_points(4, 2, 0.0)[1], 0.1), "without ignorance the grid is uniform"


def test_looked_in_one_of_two_places_and_found_nothing_believes_the_other(paper) -> None:
    _, model, s2, p2, cell = paper
    ball = model.items.index("ball")
    before = split_prior(model, ball, s2, p2)
    skate = model.items.index("skate")
    seen = [NOT_IN_VIEW] * model.n_items
    seen[skate] = 2 * s2 if model.sees[cell, s2] else NOT_IN_VIEW  # the skate is at S2, in view
    after = update_beliefs(before, BeliefModel(model, SETTINGS.r, SETTINGS.delta), Percept(cell, tuple(seen)))
    belief = ball_belief(model, after[0], ball)
    assert belief[s2] < 0.01, f"the ball was not seen in S2, yet P(S2) = {belief[s2]:.3f}"
    assert belief[p2] > 0.5 and belief.argmax() == p2, f"expected the ball believed in P2, got {belief}"


def test_r_changes_how_a_person_revises(paper) -> None:
    """Not finding the ball in S2: with r large the person thinks it was moved (anywhere out
    of view), with r small that it was in P2 all along."""
    _, model, s2, p2, cell = paper
    ball, skate = model.items.index("ball"), model.items.index("skate")
    seen = [NOT_IN_VIEW] * model.n_items
    seen[skate] = 2 * s2
    percept = Percept(cell, tuple(seen))
    p2_by_r = {}
    for r in (1.0, 8.0, 64.0):
        after = update_beliefs(
            split_prior(model, ball, s2, p2), BeliefModel(model, r, SETTINGS.delta), percept
        )
        p2_by_r[r] = ball_belief(model, after[0], ball)[p2]
    assert p2_by_r[1.0] > p2_by_r[8.0] + 0.05 > p2_by_r[64.0] + 0.1, f"P(ball in P2) by r: {p2_by_r}"


def test_the_paper_literal_update_differs(paper) -> None:
    _, model, s2, p2, cell = paper
    ball, skate = model.items.index("ball"), model.items.index("skate")
    seen = [NOT_IN_VIEW] * model.n_items
    seen[skate] = 2 * s2
    beliefs = BeliefModel(model, SETTINGS.r, SETTINGS.delta)
    rules = {
        rule: ball_belief(
            model,
            update_beliefs(split_prior(model, ball, s2, p2), beliefs, Percept(cell, tuple(seen)), rule)[0],
            ball,
        )
        for rule in ("predict", "paper")
    }
    assert not np.allclose(rules["predict"], rules["paper"]), rules
    with pytest.raises(ValueError, match="unknown belief update 'bayes'"):
        update_beliefs(split_prior(model, ball, s2, p2), beliefs, Percept(cell, tuple(seen)), "bayes")


def test_qmdp_reads_a_step_towards_where_the_person_believes(paper) -> None:
    """A person sure the ball is in S2 and one sure it is in P2 are told apart by a step that
    brings them nearer one of the two."""
    scene, model, s2, p2, _ = paper
    policy = cached_policy(scene, SETTINGS)
    ball = model.items.index("ball")
    toward_s2 = split_prior(model, ball, s2, s2)
    toward_p2 = split_prior(model, ball, p2, p2)
    beliefs = np.vstack([toward_s2, toward_p2])
    ball_lover = ball  # preference index of the ball
    spreads = {}
    for cell in range(model.n_cells):
        if model.sees[cell, s2] or model.sees[cell, p2]:
            continue
        q = policy.q[:, policy.state_slice(cell, 0), :]
        odds = [
            qmdp_likelihood(beliefs, q, move, SETTINGS.beta, SETTINGS.epsilon)[:, ball_lover]
            for move in (Move.UP, Move.DOWN, Move.LEFT, Move.RIGHT)
        ]
        ratios = [float(o[0] / o[1]) for o in odds]
        spreads[cell] = (max(ratios), min(ratios))
    best = max(spreads.values(), key=lambda m: m[0] / m[1])
    assert best[0] / best[1] > 10, f"no step tells S2 from P2 believers anywhere: {best}"


def test_graded_tracker_sees_sallys_false_belief_and_annes_true_one() -> None:
    """Anne moves the marble while Sally is out: right after, Sally (graded model, end to end
    on the engine's stream) still believes the basket, a false belief; Anne knows the box."""
    engine = Engine("sally-anne")
    tracker = MindTracker(engine.scene(), ModelSettings(belief_model="graded"), Observer.BTOM)
    tracker.observe(engine.state(), ())
    after_move = None
    while not engine.done and after_move is None:
        result = engine.step()
        tracker.observe(result.state, result.events)
        if any(e.kind.value == "drop" and e.actor == "anne" for e in result.events):
            after_move = (tracker.online("sally"), tracker.online("anne"))
    assert after_move is not None, "Anne never dropped the marble"
    sally, anne = after_move
    assert sally is not None and anne is not None
    model = tracker.model
    marble = model.items.index("marble")
    basket, box = model.locations.index("basket"), model.locations.index("box")
    assert sally.beliefs[marble, basket] > 0.8, f"Sally after the move: {sally.beliefs[marble]}"
    assert sally.false_belief[marble] > 0.8, (
        f"Sally, who did not see the move: P(false) = {sally.false_belief}"
    )
    assert marble in sally.false_beliefs, "Sally's false belief is not flagged"
    assert anne.beliefs[marble, box] > 0.8, f"Anne after the move: {anne.beliefs[marble]}"
    assert anne.false_belief[marble] < 0.2, f"Anne, who moved the marble: P(false) = {anne.false_belief}"
    assert marble not in anne.false_beliefs, "Anne, who moved the marble, is flagged"


def test_graded_uses_the_graded_factored_model_on_large_houses(caplog: pytest.LogCaptureFixture) -> None:
    import tempfile
    from pathlib import Path

    from brain.model.person.factoredperson import FactoredModel
    from brain.model.person.gradedfactored import GradedFactoredModel
    from brain.model.person.personmodel import person_model
    from sim2d.generation import write_house_episode
    from sim2d.scenario import load_scenario

    with tempfile.TemporaryDirectory() as tmp:
        path = write_house_episode(Path(tmp), rooms=8, items=4, seed=1)
        scene = Engine(load_scenario(str(path))).scene()
    model = person_model(scene, ModelSettings())
    assert isinstance(model, GradedFactoredModel), f"expected the graded factored model, got {type(model)}"
    assert isinstance(person_model(scene, ModelSettings(belief_model="point")), FactoredModel)
    with caplog.at_level("WARNING", logger="brain.model.person.personmodel"):
        person_model(scene, ModelSettings(desire_model="graded"))
    assert "favourite desires and QMDP only" in caplog.text, caplog.text


def test_bad_belief_settings_are_named() -> None:
    with pytest.raises(ValueError, match="belief_model='certain'"):
        ModelSettings(belief_model="certain")
    with pytest.raises(ValueError, match="prior_resolution=0"):
        ModelSettings(prior_resolution=0)


def test_a_spread_belief_that_includes_the_truth_is_not_a_false_belief() -> None:
    from brain.model.estimates import Estimate, false_belief_probability

    beliefs = np.array([[0.0, 0.0, 0.5, 0.5]])  # one item, half S2 (index 2), half P2 (index 3)
    point = Estimate(beliefs, np.array([0.5, 0.5]), (0, 2, 0.5), np.zeros(1))
    graded = Estimate(
        beliefs, np.array([0.5, 0.5]), (0, 2, 0.5), np.zeros(1), (np.array([1.0]), beliefs[None, :, :])
    )
    in_s2, in_s1 = (2 * 2,), (2 * 1,)  # item values: resting at S2, at S1
    assert false_belief_probability(graded, in_s2, 0.1)[0] == 0.0, "the person's own spread includes S2"
    assert false_belief_probability(graded, in_s1, 0.1)[0] == 1.0, "nothing of the person's belief is on S1"
    assert false_belief_probability(point, in_s2, 0.1)[0] == pytest.approx(0.5), (
        "read as point beliefs, half the worlds put the item elsewhere"
    )


def test_ignorance_over_many_places_is_not_a_false_belief() -> None:
    """A belief spread evenly over 12 places that include the truth gives it 1/12, less than
    ``false_belief_mass`` (0.1): read against the likeliest place's share, it is ignorance.
    A belief that puts a twentieth of the likeliest place's share on the truth is false."""
    from brain.model.estimates import Estimate, false_belief_probability

    spread = np.r_[np.full(12, 1 / 12), np.zeros(4)]  # 16 locations, 12 of them possible
    lopsided = np.r_[0.9, 0.045, np.full(14, 0.055 / 14)]
    beliefs = np.stack([spread, lopsided])[None]  # (G = 1, K = 2, L = 16)
    est = Estimate(beliefs[0], np.ones(3) / 3, (None, None, 1.0), np.zeros(2), (np.ones(1), beliefs))
    p = false_belief_probability(est, (2 * 5, 2 * 1), 0.1)
    assert p.tolist() == [0.0, 1.0], p


@pytest.mark.parametrize("n_locations", [2, 3, 4, 5, 8, 16, 30])
def test_the_prior_chance_of_a_false_belief_does_not_grow_with_the_locations(n_locations: int) -> None:
    """Of a person's initial beliefs about an item, those giving its true place nothing weigh
    the grid's own share of the non-uniform mass (so scenes of up to 4 locations keep the
    grid's prior), but at most ``stale_share`` of it: the grid alone gives them
    ``(L - 1) / (L + 1)`` at resolution 2, nearly all of it on many locations."""
    from brain.model.graded import informed_weights

    ignorance, stale = SETTINGS.ignorance, SETTINGS.stale_share
    points, grid = initial_points(n_locations, 2, ignorance)
    for truth in range(n_locations):
        weights = informed_weights(points, ignorance, stale, truth)
        assert np.isclose(weights.sum(), 1.0) and np.isclose(weights[-1 if n_locations > 2 else 1], ignorance)
        wrong = weights[points[:, truth] == 0].sum()
        grid_wrong = grid[points[:, truth] == 0].sum()
        assert np.isclose(wrong, min(grid_wrong, (1 - ignorance) * stale)), (wrong, grid_wrong)
        if n_locations <= 4:
            assert np.allclose(weights, grid), "up to 4 locations the prior is the grid's"


@pytest.mark.parametrize("predict", [True, False], ids=["predict", "paper"])
def test_the_fast_change_sum_equals_the_dense_matrix(paper, predict: bool) -> None:
    """``apply_change`` (a sum per set of affected items) is ``beliefs @ g.T`` with the dense
    ``(W, W)`` change weights, on every cell of the paper map and with items in and out of view."""
    _, model, *_ = paper
    beliefs_model = BeliefModel(model, SETTINGS.r, SETTINGS.delta)
    rng = np.random.default_rng(3)
    beliefs = rng.dirichlet(np.ones(model.n_worlds), size=5)
    beliefs.setflags(write=False)  # revisions may be shared: the input is never written
    for cell in range(0, model.n_cells, 7):
        for seen in (
            (NOT_IN_VIEW,) * model.n_items,
            tuple(2 * (cell % model.n_locations) for _ in range(model.n_items)),
        ):
            p = Percept(cell, seen)
            g = beliefs_model.change_weights(p)
            if predict:
                g = g / g.sum(axis=0, keepdims=True)
            fast = beliefs_model.apply_change(beliefs, p, predict=predict)
            assert np.allclose(fast, beliefs @ g.T, atol=1e-12), f"cell {cell}, seen {seen}"
            assert fast.flags.writeable and not np.shares_memory(fast, beliefs), (
                f"cell {cell}, seen {seen}: expected a new array (update_beliefs writes it in place)"
            )


def test_the_joint_says_what_is_nowhere() -> None:
    """Scenario 1 after A1 put the skate in S1 (step 2): her belief's most probable whole
    worlds have the skate in S1 and the ball in S2 or P2 (online: 0.60 and 0.24), and nothing in P1
    (read off the joint, not the marginals)."""
    engine = Engine("paper-1", robot="observe")
    tracker = MindTracker(engine.scene(), ModelSettings(top_worlds=4))
    tracker.observe(engine.state(), ())
    est = None
    while not engine.done and est is None:
        result = engine.step()
        tracker.observe(result.state, result.events)
        if any(label == "2" and who == "A1" for (t, who), label in tracker.labels.items()):
            est = tracker.online("A1")
    assert est is not None and est.worlds is not None, "no joint at step 2"
    from brain.model.estimates import world_text

    top = [(world_text(tracker.model, w), p) for w, p in est.top_worlds(2)]
    assert {text for text, _ in top} == {"skate@S1;ball@S2", "skate@S1;ball@P2"}, top
    assert all(p > 0.2 for _, p in top) and sum(p for _, p in top) > 0.8, top
    p1 = tracker.model.locations.index("P1")
    nothing_in_p1 = est.worlds[np.all(tracker.model.place != p1, axis=1)].sum()
    assert nothing_in_p1 > 0.99, f"P(nothing in P1) = {nothing_in_p1:.4f}"


def test_truebelief_likelihood_of_one_world_rows_is_every_rows_to_the_bit(paper):
    """``truebelief`` puts every hypothesis in the one true world after its first step; the
    decision likelihood is then read off one row, and must equal the full ``(G, W)`` product."""
    from brain.model.person.gradedperson import GradedModel
    from brain.model.person.personinterface import StepRecord

    scene, model, s2, _, cell = paper
    graded = GradedModel(scene, SETTINGS, true_world=True)
    beliefs = np.zeros((len(graded.initial), model.n_worlds))
    beliefs[:, 7] = 1.0
    q = graded.policy.q[:, graded.policy.state_slice(cell, 0), :]
    unseen = Percept(cell, (NOT_IN_VIEW,) * model.n_items)
    for action in range(q.shape[-1]):
        record = StepRecord(0, unseen, (0,) * model.n_items, None, 0.0, (cell, 0, action))
        full = qmdp_likelihood(beliefs, q, action, SETTINGS.beta, SETTINGS.epsilon)
        got = graded.decision_likelihood(beliefs, record)
        assert np.array_equal(got, full), f"action {action}: off by {np.abs(got - full).max()}"
    spread = graded.initial.copy()  # graded hypotheses: no shortcut, the full product
    record = StepRecord(0, unseen, (0,) * model.n_items, None, 0.0, (cell, 0, 0))
    full = qmdp_likelihood(spread, q, 0, SETTINGS.beta, SETTINGS.epsilon)
    assert np.array_equal(graded.decision_likelihood(spread, record), full)


def test_believed_possible_is_the_plain_product_per_column(paper) -> None:
    """``believed_possible`` computes one product per distinct feasibility column; every
    column's answer must be the one the product over all columns gives, for beliefs of every
    kind: the prior's, sharp ones, and ones whose mass sits just around the ``1e-12`` cut."""
    scene, model, _, _, _ = paper
    policy = cached_policy(scene, SETTINGS)
    beliefs = prior_beliefs(model.worlds, model.n_locations, SETTINGS.prior_resolution, SETTINGS.ignorance)[0]
    beliefs = beliefs / beliefs.sum(axis=1, keepdims=True)
    rng = np.random.default_rng(3)
    sharp = beliefs * rng.random(beliefs.shape) ** 12
    sharp /= sharp.sum(axis=1, keepdims=True)
    near_cut = np.where(sharp > 1e-3, sharp, rng.choice([3e-13, 1e-12, 3e-12], size=sharp.shape))
    worlds = rng.integers(model.n_worlds, size=60)
    faint = np.eye(model.n_worlds)[worlds] * rng.choice([5e-13, 5e-12], size=(60, 1))  # one faint world each
    checked = 0
    for cell in range(0, model.n_cells, 7):
        for held in range(model.n_items + 1):
            q = policy.q[:, policy.state_slice(cell, held), :].transpose(1, 0, 2)
            feasible = np.isfinite(q).reshape(model.n_worlds, -1)
            for b in (beliefs, sharp, near_cut, faint):
                plain = (b @ feasible.astype(np.float64)) > 1e-12
                fast = believed_possible(b, feasible)
                assert np.array_equal(fast, plain), (
                    f"cell {cell}, held {held}: {int((fast != plain).sum())} answers differ from the product"
                )
                checked += 1
    assert checked > 30, checked
