"""The tracker reads the decisions of people who act by the brain's own planner (sim2d's
``planner = "model"``) as they were made: the ground the fit's parameter recovery stands on."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

from brain.outputs.policytable import action_names, write_policy_table
from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from sim2d.engine import Engine
from sim2d.people import PlannedPerson, load_policy_table
from sim2d.scenario import load_scenario

SETTINGS = dataclasses.replace(ModelSettings(), beta=4.0, hazard=0.02)


def run(
    tmp_path: Path, ticks: int, seed: int = 5, betas: tuple[float, ...] = (4.0,)
) -> tuple[Engine, list[MindTracker]]:
    """``paper-auto`` with planned people (beta 4, hazard 0.02) for ``ticks``, read by a
    tracker per beta."""
    scenario = load_scenario("paper-auto")
    scenario = dataclasses.replace(scenario, autonomy=dataclasses.replace(scenario.autonomy, planner="model"))
    scene = Engine(scenario, check_policy=False).scene()
    table = load_policy_table(write_policy_table(tmp_path / "policy.npz", scene, SETTINGS))
    engine = Engine(scenario, seed=seed, policy=table)
    trackers = [MindTracker(scene, dataclasses.replace(SETTINGS, beta=beta)) for beta in betas]
    for _ in range(ticks):
        result = engine.step()
        for tracker in trackers:
            tracker.observe(result.state, result.events)
    return engine, trackers


def test_every_move_take_drop_and_play_is_read_as_the_action_it_was(tmp_path: Path) -> None:
    engine, (tracker,) = run(tmp_path, 1000)
    names = action_names(tracker.model.items)
    for agent, person in engine.people.items():
        assert isinstance(person, PlannedPerson)
        made = [name for _, name, _ in person.decisions if name != "stay"]
        read = [names[s.decision[2]] for s in tracker.tracks[agent].steps if s.decision is not None]
        acted = [name for name in read if name != "stay"]
        # the last decision may still be under way (a move not yet across the cell's edge)
        assert acted == made[: len(acted)] and len(made) - len(acted) <= 1, (
            f"{agent}: expected the tracker to read {made}, it read {acted}"
        )
        assert len(made) > 20, f"{agent}: expected a busy person, got {len(made)} decisions"
        stays = sum(name == "stay" for _, name, _ in person.decisions)
        assert read.count("stay") <= stays, f"{agent}: read {read.count('stay')} waits, made {stays}"


def test_the_generating_beta_explains_the_actions_better_than_a_far_lower_one(tmp_path: Path) -> None:
    """(A far higher beta explains them nearly as well: a near-rational person's few
    mistakes are also explained by other beliefs and desires. The fit's recovery test, on
    many episodes, is where beta is pinned down.)"""
    betas = (0.5, 4.0)
    _, trackers = run(tmp_path, 1500, seed=7, betas=betas)
    evidence = {
        beta: sum(t.estimates[-1].log_evidence for t in tracker.tracks.values() if t.estimates)
        for beta, tracker in zip(betas, trackers, strict=True)
    }
    assert np.isfinite(list(evidence.values())).all(), f"log-evidence by beta: {evidence}"
    assert evidence[4.0] > evidence[0.5] + 5.0, f"log-evidence by beta: {evidence}"
