"""One replayed pass gives, at every value of beta, epsilon and hazard, exactly the evidence
a fresh tracker run at that value gives (graded, truebelief and point models), and models it
cannot serve are handed back."""

from __future__ import annotations

import dataclasses

import pytest

from brain.outputs.policytable import write_policy_table
from brain.settings import ModelSettings
from bridge.recording.trace import Trace
from protocol import ClockMode, Observer
from sim2d.engine import Engine
from sim2d.people import load_policy_table
from sim2d.scenario import load_scenario
from toyroom.fitting.evidence import episode_evidence
from toyroom.fitting.replay import evidence_at_points

POINTS = [
    {"beta": b, "hazard": h, "epsilon": e} for b in (1.0, 4.0) for h in (0.01, 0.05) for e in (0.001, 0.05)
]


@pytest.fixture(scope="module")
def trace(tmp_path_factory: pytest.TempPathFactory) -> Trace:
    """600 ticks of paper-auto with people acting by the planner (beta 4, hazard 0.02)."""
    scenario = load_scenario("paper-auto")
    scenario = dataclasses.replace(scenario, autonomy=dataclasses.replace(scenario.autonomy, planner="model"))
    settings = dataclasses.replace(ModelSettings(), beta=4.0, hazard=0.02)
    path = tmp_path_factory.mktemp("replay") / "policy.npz"
    table = write_policy_table(path, Engine(scenario, check_policy=False).scene(), settings)
    engine = Engine(scenario, seed=2, policy=load_policy_table(table))
    ticks = []
    for _ in range(600):
        result = engine.step()
        ticks.append((result.state, result.events))
    return Trace(engine.info("replay", ClockMode.LOCKSTEP), tuple(ticks))


@pytest.mark.parametrize(
    ("observer", "overrides"),
    [(Observer.BTOM, {}), (Observer.TRUEBELIEF, {}), (Observer.BTOM, {"belief_model": "point"})],
    ids=["graded", "truebelief", "point"],
)
def test_one_pass_equals_a_run_per_point(trace: Trace, observer: Observer, overrides: dict[str, str]) -> None:
    base = dataclasses.replace(ModelSettings(), **overrides)  # type: ignore[arg-type]
    fast = evidence_at_points(trace, base, observer, POINTS)
    assert fast is not None, "expected this model to be replayable"
    for point, got in zip(POINTS, fast, strict=True):
        want = episode_evidence(trace, dataclasses.replace(base, **point), observer)
        assert got.actions == want.actions > 20, (
            f"at {point}: {got.actions} decisions, a run reads {want.actions}"
        )
        assert got.log_likelihood == pytest.approx(want.log_likelihood, rel=1e-9, abs=1e-9), (
            f"at {point}: replayed {got.log_likelihood}, a run gives {want.log_likelihood}"
        )
    assert len({round(e.log_likelihood, 6) for e in fast}) == len(POINTS), "every point differs"


def test_models_it_cannot_serve_are_handed_back(trace: Trace) -> None:
    lookahead = dataclasses.replace(ModelSettings(), person_planner="belief")
    assert evidence_at_points(trace, lookahead, Observer.BTOM, POINTS[:1]) is None
    assert evidence_at_points(trace, ModelSettings(), Observer.BTOM, [{"r": 2.0}]) is None


def test_value_iteration_is_shared_by_policies_that_differ_only_in_the_choice_rule() -> None:
    from brain.model.planner import cached_policy

    scene = Engine("paper-auto").scene()
    low = cached_policy(scene, dataclasses.replace(ModelSettings(), beta=1.0))
    high = cached_policy(scene, dataclasses.replace(ModelSettings(), beta=7.0, hazard=0.3))
    assert low.q is high.q, "expected one value iteration for both"
    assert not (low.likelihood == high.likelihood).all(), "the choice rule still follows beta"
