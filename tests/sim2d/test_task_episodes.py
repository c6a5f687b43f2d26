"""Task episodes (``python -m sim2d generate --kind tasks``): built so that the robot has a job."""

from __future__ import annotations

from pathlib import Path

import pytest

from sim2d.autonomous import AutonomousPerson
from sim2d.engine import Engine
from sim2d.generate import write_episode
from sim2d.scenario import load_scenario
from sim2d.tasks import TASKS, task_of


def run(path: Path, ticks: int = 700) -> tuple[list[tuple[int, str, str, str | None, str | None]], int]:
    """The people's takes and drops, and how many ticks A1 held a false belief about what they want."""
    engine = Engine(load_scenario(str(path)), seed=1)
    acts, false = [], 0
    while not engine.done and engine.world.tick < ticks:
        result = engine.step()
        acts += [
            (e.tick, e.actor, e.kind.value, e.item, e.location)
            for e in result.events
            if e.kind.value in ("take", "drop")
        ]
        assert result.truth is not None
        mind = next(m for m in result.truth.agents if m.agent == "A1")
        where = {p.item: p.location for p in result.truth.items}
        belief = next(b for b in mind.beliefs if b.item == mind.preference)
        false += {p.id: p.p for p in belief.locations}.get(where[mind.preference], 0.0) < 0.1
    return acts, false


@pytest.mark.parametrize("seed", [0, 1])
def test_an_item_moved_while_its_owner_is_away_gives_them_a_false_belief(tmp_path: Path, seed: int) -> None:
    assert task_of(seed) in ("moved", "hidden")
    path = write_episode(tmp_path, "paper", seed, kind="tasks")
    scenario = load_scenario(str(path))
    owner, mover = scenario.people
    assert owner.errand > 0 and mover.moves is not None and owner.prefers == mover.moves[0]
    acts, false = run(path)
    item, target = mover.moves
    assert (mover.id, "drop", item, target) in [a[1:] for a in acts], (
        f"the mover puts the {item} at {target}: {acts}"
    )
    assert false > 20, f"the owner comes back believing the {item} where it was (false belief ticks: {false})"


def test_a_contested_item_is_wanted_by_both(tmp_path: Path) -> None:
    seed = TASKS.index("contested")
    scenario = load_scenario(str(write_episode(tmp_path, "house-a", seed, kind="tasks")))
    assert {p.prefers for p in scenario.people} == {scenario.items[0].id}
    assert all(p.errand == 0 and p.moves is None for p in scenario.people)


def test_everyday_episodes_are_unchanged_by_the_kind_option(tmp_path: Path) -> None:
    everyday = write_episode(tmp_path / "a", "paper", 4).read_text()
    again = write_episode(tmp_path / "b", "paper", 4, kind="everyday").read_text()
    assert everyday == again and "errand" not in everyday


def test_a_move_the_owner_watched_leaves_no_false_belief(tmp_path: Path) -> None:
    """Sally-Anne's true-belief control: the owner sees the item moved before the errand."""
    seed = TASKS.index("seen")
    path = write_episode(tmp_path, "paper", seed, kind="tasks")
    scenario = load_scenario(str(path))
    owner, mover = scenario.people
    assert owner.errand_after > 0 and mover.moves is not None
    acts, false = run(path, ticks=400)
    item, target = mover.moves
    assert (mover.id, "drop", item, target) in [a[1:] for a in acts], acts
    assert false == 0, f"the owner watched the move: expected no false belief, got {false} ticks"


def test_an_errand_is_carried_through_when_told(tmp_path: Path) -> None:
    """Told where the item they want is while on an errand, the owner finishes the errand."""
    path = write_episode(tmp_path, "paper", 0, kind="tasks")
    engine = Engine(load_scenario(str(path)), seed=1)
    owner = engine.people["A1"]
    for _ in range(5):
        engine.step()
    assert isinstance(owner, AutonomousPerson) and owner.current is not None and owner.current.errand
    owner.on_informed(engine.world, owner.preference, engine.world.map.locations[0].id)
    assert owner.current is not None and owner.current.errand, "still on the errand"
    assert owner.belief.most_likely(owner.preference) == engine.world.map.locations[0].id, (
        "but it was taken in"
    )
