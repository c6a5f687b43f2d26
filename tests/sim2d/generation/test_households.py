"""Households over days (:mod:`sim2d.generation.households`): day 1 is the episode of its
seed, later days start where the day before ended, and the nights are the household's own."""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest

from protocol import EpisodeKind, EpisodeSpec, Household, Minds, Morning
from sim2d.engine import Engine
from sim2d.generation.episodes import write_episode
from sim2d.generation.households import DRIFT, drift, night
from sim2d.generation.mornings import with_beliefs

RICH_TASKS = EpisodeSpec(Minds.RICH, EpisodeKind.TASKS)
"""Rich minds, a task episode."""

MORNING = Morning(
    items={"ball": "L1", "skate": "L4", "block": "L1"},
    beliefs={"A1": {"ball": "L1", "skate": "L0"}, "A2": {"skate": "L4"}},
    favourites={"A1": "ball", "A2": "skate"},
    household="gen-house-a-s5",
    map="house-a",
)


def test_day_one_is_the_episode_of_its_seed_with_a_household_table(tmp_path: Path) -> None:
    alone = write_episode(tmp_path / "alone", "house-a", 5, RICH_TASKS).read_text()
    day1 = write_episode(tmp_path / "days", "house-a", 5, RICH_TASKS, day=1).read_text()
    assert day1.startswith(alone.replace('name = "gen-house-a-s5"', 'name = "gen-house-a-s5-d1"')), (
        "day 1 differs from the episode beyond its name"
    )
    assert tomllib.loads(day1)["household"] == {"id": "gen-house-a-s5", "day": 1}


@pytest.mark.parametrize("kind", ["tasks", "everyday"])
def test_a_later_day_starts_from_the_morning_and_loads(tmp_path: Path, kind: str) -> None:
    spec = EpisodeSpec(Minds.RICH, kind)
    path = write_episode(tmp_path, "house-a", 5, spec, day=4, morning=MORNING)
    data = tomllib.loads(path.read_text())
    assert data["household"] == {"id": "gen-house-a-s5", "day": 4}
    changed = [line for line in path.read_text().splitlines() if line.startswith("# overnight")]
    items = {item["id"]: item["at"] for item in data["items"]}
    moved = {line.split(": ")[1].split(";")[0] for line in changed}
    expected = dict(MORNING.items)
    for change in moved:  # "ball L1 -> L2"
        item, origin, _, target = change.split()
        assert expected[item] == origin, f"{change}: the night starts from the morning's {expected}"
        expected[item] = target
    assert items == expected, f"expected the morning after the night, {expected}; got {items}"
    autonomy = data["autonomy"]
    assert autonomy["knows"] == 0.0 and autonomy["stale"] == 0.0, "beliefs come from the night, not a draw"
    engine = Engine(str(path), seed=0, check_policy=False)
    assert engine.scene().household == Household(id="gen-house-a-s5", day=4)


def test_the_nights_are_the_households_own_and_only_movers_see_them() -> None:
    first = Morning(items={"ball": "L0", "skate": "L4", "block": "L1"})
    seen = {"tidy": 0, "visitor": 0, "out and back": 0}
    for day in range(2, 80):
        args = (["L0", "L1", "L2", "L3", "L4"], ["A1", "A2"], ["ball", "skate", "block"], 5, day)
        after, changes = night(MORNING, first, *args)
        again, same = night(MORNING, first, *args)
        assert (after, changes) == (again, same), "a night is drawn from the seed and the day alone"
        for change in changes:
            seen[change.rule] += 1
            if change.rule == "tidy":
                assert change.target == first.items[change.item], change
            if change.rule == "visitor":
                assert change.seen_by == (), "nobody sees a visitor"
            for person, believed in after.beliefs.items():
                if person not in change.seen_by and change.item in MORNING.beliefs.get(person, {}):
                    if not any(c.item == change.item and person in c.seen_by for c in changes):
                        assert believed[change.item] == MORNING.beliefs[person][change.item], (
                            f"{person} did not see {change} but their belief changed"
                        )
            targets = {c.target for c in changes if c.item == change.item}
            for mover in change.seen_by:
                assert after.beliefs[mover][change.item] in targets, f"{mover} made {change}"
    assert all(n > 0 for n in seen.values()), f"every rule happens on some night: {seen}"


def test_favourites_drift_at_the_stated_rate() -> None:
    import numpy as np

    rng = np.random.default_rng(3)
    trials = 20000
    changed = sum(drift({"A1": "ball"}, ["ball", "skate", "out"], rng)["A1"] != "ball" for _ in range(trials))
    rate = changed / trials
    assert abs(rate - DRIFT) < 0.0085, f"expected {DRIFT} of days (within 4 sd), got {rate:.4f}"


def test_carried_beliefs_join_a_tasks_own_and_never_override_them() -> None:
    lines = [
        "[[agents]]",
        'id = "A1"',
        'knows = ["ball"]',
        'believes = [["skate", "L3"]]',
        "",
        "[[agents]]",
        'id = "A2"',
        "",
    ]
    out = tomllib.loads("\n".join(with_beliefs(lines, MORNING.beliefs)))
    a1, a2 = out["agents"]
    assert a1["believes"] == [["skate", "L3"]], "the task's own belief about the skate wins; ball is known"
    assert a2["believes"] == [["skate", "L4"]], a2
