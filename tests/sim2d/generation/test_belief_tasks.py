"""Task episodes where only behaviour shows a false belief (``told``, ``overlooked``, ``stale``),
what a person is doing on the truth channel (``pursuit``), and replanning after a lag."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from protocol import EpisodeKind, EpisodeSpec, Pursuit
from sim2d.engine import Engine
from sim2d.generation.episodes import write_episode
from sim2d.generation.tasks import BELIEF_TASKS, seed_of, task_of
from sim2d.people.autonomous import AutonomousPerson
from sim2d.people.pursuit import Primitive, Reconsider, pursuit_of
from sim2d.scenario.scenario import load_scenario
from toyroom.evaluation.revealed import revealed

TASK_EPISODE = EpisodeSpec(kind=EpisodeKind.TASKS)
"""A task episode."""


def run(path: Path, ticks: int = 600) -> list[tuple[int, set[tuple[str, str, str]]]]:
    """Per tick, ``(person, item, place)`` of every revealed pursuit (the evaluation's reading:
    :func:`toyroom.evaluation.revealed.revealed`)."""
    engine = Engine(load_scenario(str(path)), seed=1)
    ticks_seen = []
    while not engine.done and engine.world.tick < ticks:
        result = engine.step()
        assert result.truth is not None
        shown = revealed(result.truth)
        ticks_seen.append(
            (result.truth.tick, {(person, item, place) for (person, item), place in shown.items()})
        )
    return ticks_seen


@pytest.mark.parametrize("kind", BELIEF_TASKS)
@pytest.mark.parametrize("map_name", ["paper", "house-a"])
def test_the_owner_walks_to_the_wrong_place_nothing_moved(tmp_path: Path, kind: str, map_name: str) -> None:
    seed = seed_of(kind, 1)
    assert task_of(seed) == kind
    path = write_episode(tmp_path, map_name, seed, TASK_EPISODE)
    scenario = load_scenario(str(path))
    owner = scenario.people[0]
    assert all(p.jobs.moves is None for p in scenario.people), "nothing is moved in these tasks"
    ticks = run(path)
    owner_ticks = [t for t, r in ticks if any(person == owner.id for person, _, _ in r)]
    assert len(owner_ticks) >= 5, (
        f"{kind}: expected the owner's walk to a wrong place to show, got {owner_ticks}"
    )


def test_told_happens_out_of_the_robots_hearing(tmp_path: Path) -> None:
    path = write_episode(tmp_path, "paper", seed_of("told"), TASK_EPISODE)
    engine = Engine(load_scenario(str(path)), seed=1)
    says = []
    owner, teller = engine.people["A1"], engine.people["A2"]
    assert isinstance(teller, AutonomousPerson) and teller.tells is not None
    item = teller.tells[1]
    truth = engine.world.item_location(item)
    assert isinstance(owner, AutonomousPerson) and owner.belief.most_likely(item) == truth
    while teller.tells is not None and engine.world.tick < 60:
        says += [e for e in engine.step().events if e.kind.value in ("say", "request")]
    assert says == [], f"expected no speech on the wire, got {says}"
    assert (
        owner.belief.most_likely(item) == teller.belief.most_likely(item) != engine.world.item_location(item)
    )


def test_task_kinds_can_be_chosen(tmp_path: Path) -> None:
    out = subprocess.run(
        [sys.executable, "-m", "sim2d", "generate", "--kind", "tasks", "--tasks", "stale,told"]
        + ["--episodes", "paper:0", "paper:1", "--out", str(tmp_path)],
        capture_output=True,
        text=True,
        check=True,
    )
    texts = [Path(line).read_text() for line in out.stdout.split()]
    assert "believes" in texts[0] and "errand" not in texts[0] and "tell =" in texts[1], texts
    bad = subprocess.run(
        [sys.executable, "-m", "sim2d", "generate", "--kind", "tasks", "--tasks", "stale,tolt"]
        + ["--out", str(tmp_path)],
        capture_output=True,
        text=True,
    )
    assert bad.returncode == 2 and "tolt" in bad.stderr and "overlooked" in bad.stderr, bad.stderr


def test_pursuit_reads_the_plan(tmp_path: Path) -> None:
    engine = Engine(load_scenario("paper-1"), seed=0)
    world = engine.world
    s1, p2 = world.locations["S1"], world.locations["P2"]
    here = (s1.cell.col, s1.cell.row)
    away = (0, 0)
    fetch = [Primitive("goto", cell=(p2.cell.col, p2.cell.row)), Primitive("take", item="ball")]
    assert pursuit_of(fetch, world, away) == Pursuit(item="ball", location="P2")
    assert pursuit_of(fetch[1:], world, here) == Pursuit(item="ball", location="S1")
    assert pursuit_of([Primitive("wait", ticks=3), *fetch], world, away) is None
    assert pursuit_of([Primitive("goto", cell=away), *fetch], world, away) == Pursuit(item="ball")
    put = [Primitive("goto", cell=here), Primitive("drop", location="S1")]
    assert pursuit_of(put, world, away) == Pursuit(location="S1")


def test_a_pointless_walk_is_dropped_after_the_persons_own_lag() -> None:
    import numpy as np

    rng = np.random.default_rng(0)
    reconsider = Reconsider((3, 3))
    assert [reconsider.check(True, t, rng) for t in range(10, 14)] == [False, False, False, True]
    assert reconsider.check(True, 20, rng) is False and reconsider.check(False, 21, rng) is False
    assert reconsider.check(True, 30, rng) is False and reconsider.check(True, 33, rng) is True


def test_every_map_of_an_evaluation_gets_every_kind() -> None:
    kinds = ("told", "overlooked", "stale")
    pairs = {(i % 3, task_of(1000 + i, kinds)) for i in range(40)}
    assert pairs == {(m, k) for m in range(3) for k in kinds}, sorted(pairs)
