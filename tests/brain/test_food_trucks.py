"""The scenes classic BToM stimuli need, on Baker, Saxe and Tenenbaum's food trucks
(``sim2d/scenarios/food-trucks.toml``): an absent item (the Mexican truck is not on campus),
spots that hold one truck each, and trucks used in place. The student sees the Korean
truck, walks to the gap in the wall to see what is behind it (the Lebanese truck), turns
back and eats at the Korean one."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from support import MindCsv, toyroom_run

from brain.model.desires import ranking_text
from brain.model.estimates import Estimate, false_belief_probability
from brain.model.planner import use_action
from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from sim2d.engine import Engine


def follow(settings: ModelSettings) -> MindTracker:
    engine = Engine("food-trucks", robot="observe")
    tracker = MindTracker(engine.scene(), settings)
    tracker.observe(engine.state(), ())
    while not engine.done:
        result = engine.step()
        tracker.observe(result.state, result.events)
    return tracker


@pytest.fixture(scope="module")
def graded() -> MindTracker:
    return follow(ModelSettings(desire_model="graded"))


def at(tracker: MindTracker, label: str) -> tuple[int, int]:
    """``(tick, index of the student's last step by then)`` of the step ``label``."""
    tick = next(t for (t, who), name in tracker.labels.items() if who == "student" and name == label)
    steps = tracker.tracks["student"].steps
    return tick, max(i for i, s in enumerate(steps) if s.tick <= tick)


def false_belief(tracker: MindTracker, est: Estimate, tick: int, item: str) -> float:
    mass = tracker.settings.false_belief_mass
    return float(false_belief_probability(est, tracker.truths[tick], mass)[tracker.model.items.index(item)])


def test_an_absent_item_is_somewhere_the_student_may_wrongly_believe_it(graded: MindTracker) -> None:
    """Before looking behind the wall, the student (who walks there) may believe the Mexican
    truck is at E1: a false belief, since it is absent. Once E1 shows the Lebanese truck and
    W1 the Korean one, each spot holding one truck, she knows it is nowhere."""
    model = graded.model
    assert model.locations[-1] == "absent", f"locations: {model.locations}"
    mexican = model.items.index("mexican")
    smoothed = graded.smoothed("student")
    start, i = at(graded, "start")
    before = false_belief(graded, smoothed[i], start, "mexican")
    assert smoothed[i].beliefs[mexican, model.locations.index("E1")] > 0.6, smoothed[i].beliefs[mexican]
    assert before > 0.5, (
        f"at the start: P(false belief about the absent truck) = {before:.3f}, expected > 0.5"
    )
    look, j = at(graded, "look")
    after = graded.tracks["student"].estimates[j]
    assert after.beliefs[mexican, -1] > 0.99, f"after looking: {after.beliefs[mexican]}"
    assert false_belief(graded, after, look, "mexican") < 0.01


def test_a_spot_holds_one_truck(graded: MindTracker) -> None:
    """No world of the joint puts two trucks at one spot (``capacity = 1``): exactly zero."""
    model = graded.model
    resting = model.worlds % 2 == 0
    crowded = np.zeros(model.n_worlds, dtype=bool)
    for spot in (model.locations.index("W1"), model.locations.index("E1")):
        crowded |= ((model.place == spot) & resting).sum(axis=1) > 1
    assert crowded.any() and not model.allowed[crowded].any()
    for est in graded.tracks["student"].estimates:
        assert est.worlds is not None and est.worlds[crowded].sum() == 0.0


def test_eating_in_place_is_a_use_decision(graded: MindTracker) -> None:
    """The ``use`` event is the planner's Use(korean): the Korean truck is used where it stands."""
    model = graded.model
    eat, i = at(graded, "eat")
    step = graded.tracks["student"].steps[i]
    assert step.tick == eat and step.decision is not None
    assert step.decision[2] == use_action(model.n_items, model.items.index("korean")), step.decision


def test_the_student_wanted_the_absent_truck_most(graded: MindTracker) -> None:
    """Baker et al.'s reading: Mexican > Korean > Lebanese. With graded desires it is the
    most probable ranking at the end; with one favourite the model cannot rank the rest."""
    eat, i = at(graded, "eat")
    est = graded.smoothed("student")[i]
    assert est.desire is not None
    goals = (*graded.model.items, "out")
    korean, lebanese, mexican = (graded.model.items.index(t) for t in ("korean", "lebanese", "mexican"))
    ranking = ranking_text(est.desire.ranking, goals)
    assert ranking.startswith("mexican>korean") and ranking.endswith("lebanese"), ranking
    assert est.desire.preferred[mexican, korean] > 0.6, est.desire.preferred
    assert est.desire.preferred[korean, lebanese] > 0.6, est.desire.preferred


@pytest.mark.parametrize("engine", ["sim2d", "grid"])
def test_food_trucks_over_zenoh(tmp_path: Path, engine: str) -> None:
    """The same scene through the protocol, on both engines: engine and brain processes,
    absent items, use locations and use events on the wire."""
    out = toyroom_run(tmp_path, "food-trucks", "--robot", "observe", "--no-live", "--engine", engine)
    mind = MindCsv(out / "mind.csv")
    eat = mind.tick("student", "eat")
    assert mind.belief("student", eat, "mexican", "absent", "p_online") > 0.99
    assert any(r["quantity"] == "desire" for r in mind.rows), "no desire rows"
    assert any(r["quantity"] == "world" for r in mind.rows), "no world rows"
    assert "use" in (out / "events.csv").read_text()
    evidence = [float(r["p_smoothed"]) for r in mind.rows if r["quantity"] == "log_evidence"]
    assert evidence and evidence[0] < 0.0, "no log-evidence of the student's decisions"
    assert "## Log-evidence" in (out / "report.md").read_text()
