"""Generated episodes: named so they never collide with a bundled scenario, free of absolute
paths (a folder of them can be moved), and given no paper ground truth."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from brain.outputs.groundtruth import load_ground_truth
from sim2d.generation.episodes import MAPS, map_of, write_episode, write_house_episode
from sim2d.scenario.scenario import load_scenario, scenario_names


@pytest.mark.parametrize("map_name", sorted(MAPS))
def test_generated_episodes_are_named_apart_and_movable(map_name: str, tmp_path: Path) -> None:
    made = tmp_path / "made"
    path = write_episode(made, map_name, seed=1)
    assert path.name == f"gen-{map_name}-s1.toml", path.name
    for file in made.iterdir():
        assert str(tmp_path) not in file.read_text(), f"{file.name} embeds the absolute path {tmp_path}"
    moved = tmp_path / "moved"
    shutil.move(made, moved)
    scenario = load_scenario(str(moved / path.name))
    assert scenario.name == f"gen-{map_name}-s1"
    assert scenario.name not in scenario_names()
    assert map_of(scenario.name) == map_name
    assert load_ground_truth(scenario.name) is None, "a generated episode got a paper ground truth"


def test_generated_houses_are_named_apart(tmp_path: Path) -> None:
    path = write_house_episode(tmp_path, rooms=4, items=2, seed=3)
    assert path.name == "gen-house-4r2i-s3.toml"
    assert map_of(load_scenario(str(path)).name) == "house-4r2i"


def test_map_of_rejects_other_names() -> None:
    with pytest.raises(ValueError, match="paper-1"):
        map_of("paper-1")
