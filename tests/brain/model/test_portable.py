"""Items a scene declares fixed (``ItemSpec.portable = false``, protocol 1.4): never carried
in any world the brain considers, and belief rows over resting places only.

On the food-truck stimulus (``sim2d/scenarios/food-trucks.toml``: two spots of capacity 1,
the trucks used in place, one truck absent) with the trucks declared fixed, and, for
contrast, as the scenario declares them (portable), where the belief update's change of
world moves mass onto "carried near a spot" and so over-counts a capacity-1 spot."""

from __future__ import annotations

import msgspec
import numpy as np
import pytest

from brain.model.factored import factored_prior
from brain.model.planner import TAKE
from brain.model.world import build_world_model
from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from protocol import Scene
from sim2d.engine import Engine


def fixed(scene: Scene) -> Scene:
    """``scene`` with every item declared not portable."""
    items = tuple(msgspec.structs.replace(item, portable=False) for item in scene.items)
    return msgspec.structs.replace(scene, items=items)


def follow(settings: ModelSettings, fixed_trucks: bool) -> MindTracker:
    engine = Engine("food-trucks", robot="observe")
    scene = fixed(engine.scene()) if fixed_trucks else engine.scene()
    tracker = MindTracker(scene, settings)
    tracker.observe(engine.state(), ())
    while not engine.done:
        result = engine.step()
        tracker.observe(result.state, result.events)
    return tracker


def spot_totals(tracker: MindTracker) -> list[float]:
    """Per estimate (online and smoothed), the largest over the capacity-1 spots of the
    summed probability that each truck is believed there."""
    model = tracker.model
    spots = [model.locations.index(s) for s in ("W1", "E1")]
    ests = [*tracker.tracks["student"].estimates, *tracker.smoothed("student")]
    return [float(est.beliefs[:, spots].sum(axis=0).max()) for est in ests]


def test_a_fixed_item_is_never_held_in_any_allowed_world() -> None:
    scene = Engine("food-trucks", robot="observe").scene()
    model = build_world_model(fixed(scene))
    assert not model.portable.any()
    held = (model.worlds % 2 == 1).any(axis=1)
    assert held.any() and not model.allowed[held].any(), "a world with a fixed truck carried is allowed"
    assert not model.value_ok[:, 1::2].any(), model.value_ok
    portable = build_world_model(scene)
    assert portable.portable.all() and portable.allowed[held].any(), "portable trucks may be carried"


def test_no_one_plans_to_take_a_fixed_item() -> None:
    """The planner's Take of a fixed item is infeasible everywhere (exact and factored)."""
    from brain.model.factored import focus_transitions
    from brain.model.planner import INFEASIBLE, transitions

    model = build_world_model(fixed(Engine("food-trucks", robot="observe").scene()))
    trans = transitions(model)
    takes = trans.next_state[:, TAKE : TAKE + model.n_items]
    assert (takes == INFEASIBLE).all(), "some state lets a person take a fixed truck"
    focus = focus_transitions(model, 0)
    assert (focus.next_state[:, TAKE] == INFEASIBLE).all(), "the factored MDP takes a fixed truck"


def test_the_factored_prior_puts_nothing_on_a_fixed_item_carried() -> None:
    model = build_world_model(fixed(Engine("food-trucks", robot="observe").scene()))
    prior = factored_prior(model)
    assert np.all(prior.beliefs[..., 1::2] == 0.0), prior.beliefs[0]
    np.testing.assert_allclose(prior.beliefs.sum(axis=-1), 1.0)


@pytest.mark.parametrize("belief_model", ["graded", "point"])
def test_a_capacity_1_spot_holds_at_most_one_fixed_truck_in_belief(belief_model: str) -> None:
    """The issue's defect: P(L at spot) + P(M at spot) came to 1.14 at a capacity-1 spot,
    counting "carried near the spot" as at it. With the trucks fixed, the rows sum to at
    most 1 at every step, online and smoothed; with them portable (the contrast), they do not."""
    settings = ModelSettings(belief_model=belief_model)
    totals = spot_totals(follow(settings, fixed_trucks=True))
    assert max(totals) <= 1.0 + 1e-9, f"expected at most 1 truck believed at a spot, got {max(totals):.4f}"
    if belief_model == "graded":
        contrast = spot_totals(follow(settings, fixed_trucks=False))
        assert max(contrast) > 1.0 + 1e-6, (
            f"portable trucks: expected some over-count, got {max(contrast):.4f}"
        )


def held_mass(tracker: MindTracker) -> float:
    """The factored filter's probability, at the end, that some truck is believed carried
    (summed over preferences' beliefs ``(D, K, V)``, the held values ``2 l + 1``)."""
    run = tracker.tracks["student"].chains[0].filter
    beliefs = run.posterior.beliefs if hasattr(run, "posterior") else run.beliefs  # type: ignore[union-attr]
    return float(beliefs[..., 1::2].sum(axis=-1).max())


@pytest.mark.parametrize("belief_model", ["graded", "point"])
def test_factored_beliefs_of_a_fixed_item_stay_on_resting_places(belief_model: str) -> None:
    """The factored model (above ``exact_max_worlds``): no belief in a fixed truck carried,
    where portable trucks get some (the factored model keeps no capacities: its rows per
    item are independent, so a spot's total is not checked here)."""
    settings = ModelSettings(exact_max_worlds=1, belief_model=belief_model)
    tracker = follow(settings, fixed_trucks=True)
    assert not tracker.model.portable.any()
    assert held_mass(tracker) == 0.0, f"expected no belief in a carried fixed truck, got {held_mass(tracker)}"
    contrast = held_mass(follow(settings, fixed_trucks=False))
    assert contrast > 1e-3, f"portable trucks: expected some belief in one carried, got {contrast}"
