"""The factored models' smoother: exact where the product form is (one item), close to the
exact model's forward-backward on the paper map, fixed-lag between the filter and the full
smoother."""

from __future__ import annotations

import numpy as np
import pytest

from brain.model.estimates import Estimate
from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from sim2d.engine import Engine


def _trackers(scenario: str, belief_model: str) -> tuple[MindTracker, MindTracker]:
    """The exact and the factored tracker over the whole of ``scenario`` (robot observing)."""
    engine = Engine(scenario, robot="observe")
    exact = MindTracker(engine.scene(), ModelSettings(belief_model=belief_model, exact_max_worlds=1 << 62))
    factored = MindTracker(engine.scene(), ModelSettings(belief_model=belief_model, exact_max_worlds=0))
    assert exact.exact and not factored.exact
    states = [(engine.state(), ())]
    while not engine.done:
        result = engine.step()
        states.append((result.state, result.events))
    for state, events in states:
        exact.observe(state, events)
        factored.observe(state, events)
    return exact, factored


def _tv(a: list[Estimate], b: list[Estimate]) -> tuple[float, float]:
    """Mean total variation between two runs of estimates: item beliefs, preferences."""
    assert len(a) == len(b) > 0
    pairs = list(zip(a, b, strict=True))
    beliefs = np.mean([0.5 * np.abs(x.beliefs - y.beliefs).sum(axis=1).mean() for x, y in pairs])
    preferences = np.mean([0.5 * np.abs(x.preference - y.preference).sum() for x, y in pairs])
    return float(beliefs), float(preferences)


@pytest.mark.parametrize("belief_model", ["point", "graded"])
def test_with_one_item_the_factored_smoother_is_the_exact_one(belief_model: str) -> None:
    exact, factored = _trackers("sally-anne", belief_model)
    assert exact.model.n_items == 1
    for person in exact.people:
        beliefs, preferences = _tv(exact.smoothed(person), factored.smoothed(person))
        online = _tv(exact.smoothed(person), factored.tracks[person].chains[0].estimates)[1]
        assert beliefs < 1e-3 and preferences < 1e-3, f"{person}: expected equal, tv {beliefs}, {preferences}"
        assert online > 0.05, (
            f"{person}: smoothing should matter here: expected the online preferences more than "
            f"0.05 away, got {online}"
        )


@pytest.mark.parametrize("belief_model", ["point", "graded"])
def test_on_the_paper_map_the_factored_smoother_stays_near_the_exact_one(belief_model: str) -> None:
    exact, factored = _trackers("paper-2", belief_model)
    for person in exact.people:
        reference = exact.smoothed(person)
        smoothed = _tv(reference, factored.smoothed(person))
        online = _tv(reference, factored.tracks[person].chains[0].estimates)
        assert max(smoothed) <= 0.05, f"{person}: tv against the exact smoother {smoothed}, want <= 0.05"
        assert smoothed[1] < online[1] / 4, f"{person}: smoothed {smoothed}, want far nearer than {online}"


@pytest.mark.parametrize("belief_model", ["point", "graded"])
def test_fixed_lag_runs_from_the_filter_to_the_full_smoother(belief_model: str) -> None:
    _, factored = _trackers("paper-2", belief_model)
    chain = factored.tracks["A1"].chains[0]
    model = factored.person_model
    full = model.smoothed(chain.steps, chain.estimates)
    assert max(_tv(model.smoothed(chain.steps, chain.estimates, lag=0), chain.estimates)) < 1e-12
    assert max(_tv(model.smoothed(chain.steps, chain.estimates, lag=len(chain.steps)), full)) < 1e-12
    gaps = [_tv(model.smoothed(chain.steps, chain.estimates, lag=lag), full)[1] for lag in (1, 4, 16)]
    assert gaps[0] > gaps[2], f"a longer lag should come nearer the full smoother, got {gaps}"
