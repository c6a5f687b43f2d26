"""People who act by the brain's planner (``Autonomy.planner = "model"``): the table the
brain writes (``python -m brain plan``, run as a process: sim2d never imports the brain),
the choice rule, the hazard, and what a near-rational person does on the paper map."""

from __future__ import annotations

import dataclasses
import subprocess
import sys
from pathlib import Path

import msgspec
import numpy as np
import pytest

from protocol import Scene
from sim2d.engine import Engine
from sim2d.errors import ScenarioError
from sim2d.people.planned import PlannedPerson
from sim2d.people.policytable import PolicyTable, PolicyTableError, load_policy_table
from sim2d.scenario.scenario import Scenario, load_scenario


def planned_scenario(**knobs: object) -> Scenario:
    """``paper-auto`` with people who act by the planner."""
    scenario = load_scenario("paper-auto")
    autonomy = dataclasses.replace(scenario.autonomy, planner="model", **knobs)
    return dataclasses.replace(scenario, autonomy=autonomy)


def write_table(tmp: Path, scenario: str, *overrides: str) -> Path:
    """``python -m sim2d scene`` then ``python -m brain plan``, as the evaluation runs them."""
    scene = subprocess.run(
        [sys.executable, "-m", "sim2d", "scene", "--scenario", scenario],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    scene_path = tmp / "scene.json"
    scene_path.write_text(scene)
    out = tmp / f"policy-{len(overrides)}-{abs(hash(overrides))}.npz"
    sets = [arg for o in overrides for arg in ("--set", o)]
    subprocess.run(
        [sys.executable, "-m", "brain", "plan", "--scene", str(scene_path), "--out", str(out), *sets],
        capture_output=True,
        text=True,
        check=True,
    )
    return out


@pytest.fixture(scope="module")
def sharp(tmp_path_factory: pytest.TempPathFactory) -> PolicyTable:
    """The paper-auto table of a near-rational person (beta 50, no floor, no switching)."""
    tmp = tmp_path_factory.mktemp("sharp")
    return load_policy_table(write_table(tmp, "paper-auto", "beta=50", "epsilon=0", "hazard=0"))


def planned(engine: Engine, agent: str) -> PlannedPerson:
    person = engine.people[agent]
    assert isinstance(person, PlannedPerson), f"expected a planned person, got {type(person).__name__}"
    return person


def test_the_table_names_its_axes_and_carries_the_settings(sharp: PolicyTable) -> None:
    D, C, H, W, A = sharp.q.shape
    assert (D, H, A) == (3, 3, 2 * 2 + 7), f"paper-auto: 2 items, 3 goals; got q of shape {sharp.q.shape}"
    assert sharp.goals == ("skate", "ball", "out") and sharp.items == ("skate", "ball")
    assert W == len(sharp.worlds) == (2 * len(sharp.locations)) ** 2
    assert C == len(sharp.cell_index)
    assert (sharp.beta, sharp.epsilon, sharp.hazard) == (50.0, 0.0, 0.0)


def test_the_engine_refuses_planned_people_without_a_table_or_with_another_scenes() -> None:
    with pytest.raises(ScenarioError, match="--policy"):
        Engine(planned_scenario())


def test_a_table_of_another_scene_is_refused(tmp_path: Path) -> None:
    table = load_policy_table(write_table(tmp_path, "sally-anne"))
    with pytest.raises(PolicyTableError, match="made for another scene"):
        Engine(planned_scenario(), policy=table)


def test_a_broken_table_file_is_a_clear_error(tmp_path: Path) -> None:
    path = tmp_path / "broken.npz"
    np.savez(path, q=np.zeros(3))
    with pytest.raises(PolicyTableError, match="missing cells"):
        load_policy_table(path)
    path.write_bytes(b"not a table")
    with pytest.raises(PolicyTableError, match="cannot be read"):
        load_policy_table(path)


def test_beta_zero_chooses_uniformly_among_the_possible_actions(tmp_path: Path) -> None:
    table = load_policy_table(write_table(tmp_path, "paper-auto", "beta=0", "epsilon=0"))
    cell = next(iter(table.cell_index.values()))
    belief = np.full(len(table.worlds), 1.0 / len(table.worlds))
    p = table.choice(0, cell, 0, belief)
    possible = p > 0
    assert p.sum() == pytest.approx(1.0)
    assert np.allclose(p[possible], 1.0 / possible.sum()), f"expected uniform over possible actions, got {p}"


def test_a_near_rational_person_walks_straight_to_where_they_believe_their_item_is(
    sharp: PolicyTable,
) -> None:
    engine = Engine(planned_scenario(), seed=3, policy=sharp)
    person = planned(engine, "A1")
    person.preference = "ball"
    person.belief.told("ball", "S2")  # it is there (paper-auto)
    planned(engine, "A2").preference = "out"
    spot = engine.world.locations["S2"].cell
    start = engine.world.agents["A1"].cell
    far = abs(start[0] - spot.col) + abs(start[1] - spot.row)
    for _ in range(400):
        engine.step()
        if any(name == "take:ball" for _, name, _ in person.decisions):
            break
    names = [name for _, name, _ in person.decisions]
    assert "take:ball" in names, f"expected A1 to take the ball at S2, decided {names}"
    moves = names[: names.index("take:ball")]
    assert len(moves) == far, f"expected {far} moves on a shortest path from {start} to S2, got {moves}"
    chances = [round(p, 3) for _, _, p in person.decisions]
    assert min(chances) > 0.49, f"at beta 50 every decision is one of at most two best, got {chances}"


def test_hazard_one_redraws_the_preference_at_every_decision(tmp_path: Path) -> None:
    """A redraw from all the goals, which may keep the one held (the brain's model): with a
    hazard of one the preference at each decision is drawn anew, so it repeats at times
    (never under the rule before, a switch to another goal) and takes every goal."""
    table = load_policy_table(write_table(tmp_path, "paper-auto", "hazard=0.999999"))
    engine = Engine(planned_scenario(), seed=1, policy=table)
    person = planned(engine, "A2")
    seen = []
    for _ in range(120):
        before = len(person.decisions)
        engine.step()
        if len(person.decisions) > before:
            seen.append(person.preference)
    assert len(seen) >= 5, f"expected several decisions in 120 ticks, got {len(seen)}"
    repeats = sum(a == b for a, b in zip(seen[1:], seen[2:], strict=False))
    assert repeats >= 1 and set(seen) == set(person.options), (
        f"expected preferences drawn anew at every decision (some repeats, every goal), got {seen}"
    )


def test_the_scene_command_prints_the_scene_the_engine_serves() -> None:
    out = subprocess.run(
        [sys.executable, "-m", "sim2d", "scene", "--scenario", "paper-auto"],
        capture_output=True,
        check=True,
    ).stdout
    assert msgspec.json.decode(out, type=Scene) == Engine("paper-auto").scene()
