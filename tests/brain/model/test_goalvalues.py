"""Graded desires that plan fast (issue 39): the closed-form solver of
:mod:`brain.model.goalvalues` gives value iteration's Q-values, ``out`` is not graded where a
scene has no outside, and planning says how far it got."""

from __future__ import annotations

import logging

import msgspec
import numpy as np
import pytest

from brain.model.desires import utilities
from brain.model.planner import rewards, solve, transitions, value_iteration
from brain.model.world import build_world_model
from brain.settings import ModelSettings
from protocol import RegionKind, Scene
from sim2d.engine import Engine
from tests.scenes import tiny_scene


def closed(scene: Scene) -> Scene:
    """``scene`` without its outside regions, the doors to them and their cells' sight."""
    outside = {r.id for r in scene.regions if r.kind is RegionKind.OUTSIDE}
    doors = tuple(d for d in scene.doors if not set(d.joins) & outside)
    walkable = {(c.col, c.row) for r in scene.regions if r.id not in outside for c in r.cells}
    walkable |= {(d.cell.col, d.cell.row) for d in doors}
    return msgspec.structs.replace(
        scene,
        regions=tuple(r for r in scene.regions if r.id not in outside),
        doors=doors,
        visibility=tuple(v for v in scene.visibility if (v.cell.col, v.cell.row) in walkable),
        agents=tuple(msgspec.structs.replace(a, home=scene.regions[0].cells[-1]) for a in scene.agents),
    )


def iterated(scene: Scene, settings: ModelSettings) -> tuple[np.ndarray, np.ndarray]:
    """The candidates and their Q-values by value iteration, one candidate at a time."""
    model = build_world_model(scene)
    trans = transitions(model)
    u = utilities(settings, model.n_items, leaves=bool(model.outside.any()))
    q = np.stack(
        [value_iteration(trans, rewards(model, trans, settings, r), settings.discount, 1e-12) for r in u]
    )
    return u, q


@pytest.mark.parametrize("desire_model", ["favourite", "graded"])
@pytest.mark.parametrize("scene_name", ["tiny", "tiny-closed", "paper-2", "food-trucks"])
def test_the_closed_form_is_value_iterations_fixed_point(scene_name: str, desire_model: str) -> None:
    scene = {"tiny": tiny_scene(), "tiny-closed": closed(tiny_scene())}.get(scene_name)
    if scene is None:
        scene = Engine(scene_name).scene()
    settings = ModelSettings(desire_model=desire_model)
    u, q = solve(build_world_model(scene), settings)
    u_ref, q_ref = iterated(scene, settings)
    np.testing.assert_array_equal(u, u_ref)
    finite = np.isfinite(q_ref)
    assert np.array_equal(finite, np.isfinite(q)), (
        "the closed form and value iteration differ in what is feasible"
    )
    worst = float(np.abs(q[finite] - q_ref[finite]).max())
    assert worst < 1e-8, f"expected value iteration's Q-values (within 1e-8), got a difference of {worst:.2e}"


def test_value_iteration_is_kept_where_a_goal_is_worth_less_than_standing() -> None:
    """The closed form assumes no goal is worth less than standing forever; with a negative
    leaving utility below ``-step_cost / (1 - discount)`` the planner iterates instead."""
    settings = ModelSettings(leave_utility_item=-40.0, leave_utility_out=-30.0)
    u, q = solve(build_world_model(tiny_scene()), settings)
    u_ref, q_ref = iterated(tiny_scene(), settings)
    finite = np.isfinite(q_ref)
    worst = float(np.abs(q[finite] - q_ref[finite]).max())  # to vi_tolerance: standing converges slowly
    assert worst < 1e-6, f"expected value iteration's Q-values (within 1e-6), got a difference of {worst:.2e}"


def test_graded_desires_leave_out_ungraded_without_an_outside() -> None:
    """No outside: ``out`` stays at its low utility and only the items are graded
    (``3**K - 1`` candidates, not ``3**(K + 1) - 1``); with an outside it is graded."""
    settings = ModelSettings(desire_model="graded")
    model = build_world_model(closed(tiny_scene()))
    assert not model.outside.any()
    u, _ = solve(model, settings)
    assert u.shape == (3**model.n_items - 1, model.n_items + 1), u.shape
    assert np.all(u[:, -1] == settings.leave_utility_item), u[:, -1]
    assert len(np.unique(u, axis=0)) == len(u), "two candidates are the same vector"
    open_u, _ = solve(build_world_model(tiny_scene()), settings)
    assert len(open_u) == 3 ** (model.n_items + 1) - 1
    assert len(np.unique(open_u[:, -1])) == 3


def test_planning_logs_how_many_candidates_and_how_long(caplog: pytest.LogCaptureFixture) -> None:
    with caplog.at_level(logging.INFO, logger="brain.model.goalvalues"):
        solve(build_world_model(tiny_scene()), ModelSettings(desire_model="graded"))
    lines = [r.getMessage() for r in caplog.records]
    assert any(line.startswith("planning 8 candidate desires over") for line in lines), lines
    assert any(
        line.startswith("planned 8 of 8 candidate desires in") and line.endswith(" s") for line in lines
    ), lines
