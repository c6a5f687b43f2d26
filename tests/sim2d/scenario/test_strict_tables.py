"""Scenario and map files are strict: a misspelt key in any table is an error naming it, the
closest known key and every known key; and a scenario naming a map plays the file of that
name beside it before the bundled one, so a copied scenario plays its copied map."""

from __future__ import annotations

import shutil
from pathlib import Path

import pytest

from protocol import EpisodeSpec
from sim2d.errors import ScenarioError
from sim2d.generation.episodes import KINDS, MINDS, write_episode, write_house_episode
from sim2d.generation.tasks import TASKS
from sim2d.scenario.autonomy import AUTONOMY_KEYS
from sim2d.scenario.maps import SCENARIO_DIR, load_map
from sim2d.scenario.scenario import load_scenario
from sim2d.scenario.tables import (
    AGENT_KEYS,
    DOOR_KEYS,
    ITEM_KEYS,
    LOCATION_KEYS,
    MAP_KEYS,
    REGION_KEYS,
    SCENARIO_KEYS,
    VISIBILITY_KEYS,
)

PAPER_MAP = (SCENARIO_DIR / "paper.map.toml").read_text()
PAPER_AUTO = (SCENARIO_DIR / "paper-auto.toml").read_text()


def _assert_names(err: ScenarioError, key: str, closest: str | None, known: frozenset[str]) -> None:
    """The message names the unknown key, the closest known one (or says none is close) and
    every known key."""
    text = str(err)
    hint = f"did you mean '{closest}'?" if closest else "none of the known is close"
    assert f"unknown key '{key}' ({hint})" in text, text
    assert "known keys: " + ", ".join(sorted(known)) in text, text


def _scenario_error(tmp_path: Path, old: str, new: str) -> ScenarioError:
    assert old in PAPER_AUTO, old
    text = PAPER_AUTO.replace(old, new, 1)
    path = tmp_path / "misspelt.toml"
    path.write_text(text.replace('map = "paper"', f'map = "{(SCENARIO_DIR / "paper.map.toml").as_posix()}"'))
    with pytest.raises(ScenarioError) as caught:
        load_scenario(str(path))
    assert caught.value.path == path, caught.value
    return caught.value


@pytest.mark.parametrize(
    ("old", "new", "entry", "key", "closest", "known"),
    [
        ("max_ticks = ", "max_tiks = ", "", "max_tiks", "max_ticks", SCENARIO_KEYS),
        ('id = "A1"', 'id = "A1"\nspeeed = 2', "agents[0] 'A1'", "speeed", None, AGENT_KEYS),
        ('id = "A2"', 'id = "A2"\nerand = 40', "agents[1] 'A2'", "erand", "errand", AGENT_KEYS),
        ('id = "A2"', 'id = "A2"\nhom = [5, 5]', "agents[1] 'A2'", "hom", "home", AGENT_KEYS),
        ('id = "ball"', 'id = "ball"\ncolour = "red"', "items[1] 'ball'", "colour", None, ITEM_KEYS),
        ('id = "skate"', 'id = "skate"\nshap = "board"', "items[0] 'skate'", "shap", "shape", ITEM_KEYS),
        ("switch = ", "swich = ", "autonomy", "swich", "switch", AUTONOMY_KEYS),
    ],
)
def test_an_unknown_scenario_key_is_named_with_the_closest_and_the_known_ones(
    tmp_path: Path, old: str, new: str, entry: str, key: str, closest: str | None, known: frozenset[str]
) -> None:
    err = _scenario_error(tmp_path, old, new)
    assert err.entry == entry, err
    _assert_names(err, key, closest, known)


@pytest.mark.parametrize(
    ("old", "new", "entry", "key", "closest", "known"),
    [
        ("rows = ", "wals = 3\nrows = ", "", "wals", None, MAP_KEYS),
        ("columns = ", "colums = 10\ncolumns = ", "", "colums", "columns", MAP_KEYS),
        ("rects = [[0, 8, 3, 3]]", "rect = [[0, 8, 3, 3]]", "regions[0] 'P1'", "rect", "rects", REGION_KEYS),
        ('joins = ["P1", "S1"]', 'join = ["P1", "S1"]', "doors[0] 'P1-S1'", "join", "joins", DOOR_KEYS),
        ("play = true", "plays = true", "locations[0] 'P1'", "plays", "play", LOCATION_KEYS),
        ('sees = ["E"]', 'see = ["E"]', "visibility[2]", "see", "sees", VISIBILITY_KEYS),
    ],
)
def test_an_unknown_map_key_is_named_with_the_closest_and_the_known_ones(
    tmp_path: Path, old: str, new: str, entry: str, key: str, closest: str | None, known: frozenset[str]
) -> None:
    assert old in PAPER_MAP, old
    path = tmp_path / "misspelt.map.toml"
    path.write_text(PAPER_MAP.replace(old, new, 1))
    with pytest.raises(ScenarioError) as caught:
        load_map(str(path))
    assert caught.value.path == path and caught.value.entry == entry, caught.value
    _assert_names(caught.value, key, closest, known)


def test_every_unknown_key_of_a_table_is_named(tmp_path: Path) -> None:
    err = _scenario_error(tmp_path, 'id = "A1"', 'id = "A1"\nspeeed = 2\nhom = [1, 1]')
    assert "unknown keys 'speeed' (none of the known is close), 'hom' (did you mean 'home'?)" in str(err), err


def test_a_table_where_an_array_of_tables_belongs_is_named(tmp_path: Path) -> None:
    path = tmp_path / "single.toml"
    path.write_text(
        f'name = "single"\nmap = "{(SCENARIO_DIR / "paper.map.toml").as_posix()}"\n[agents]\nid = "A1"\n'
    )
    with pytest.raises(ScenarioError, match=r"expected an array of tables \(\[\[agents\]\]\)") as caught:
        load_scenario(str(path))
    assert caught.value.entry == "agents", caught.value


def test_a_copied_scenario_plays_the_map_beside_it(tmp_path: Path) -> None:
    """``map = "sally-anne"`` with ``sally-anne.map.toml`` beside the scenario: that file, not
    the bundled one, so editing the copied map changes what is played."""
    shutil.copy(SCENARIO_DIR / "sally-anne.toml", tmp_path)
    bundled = (SCENARIO_DIR / "sally-anne.map.toml").read_text()
    edited = bundled.replace(
        'id = "box"\nregion = "room"\ncell = [4, 4]', 'id = "box"\nregion = "room"\ncell = [4, 3]'
    )
    assert edited != bundled
    (tmp_path / "sally-anne.map.toml").write_text(edited)
    scenario = load_scenario(str(tmp_path / "sally-anne.toml"))
    assert scenario.map.path == tmp_path / "sally-anne.map.toml", scenario.map.path
    box = scenario.map.location("box")
    assert (box.cell.col, box.cell.row) == (4, 3), "the edit to the copied map was not played"


def test_a_scenario_alone_plays_the_bundled_map(tmp_path: Path) -> None:
    shutil.copy(SCENARIO_DIR / "sally-anne.toml", tmp_path)
    assert load_scenario(str(tmp_path / "sally-anne.toml")).map.path == SCENARIO_DIR / "sally-anne.map.toml"


def test_every_kind_of_generated_episode_loads(tmp_path: Path) -> None:
    """Every ``[[agents]]`` key the generator writes (errand, move_after, tell, believes,
    overlooks, autonomous, home, prefers...) and every ``[autonomy]`` key is a known one."""
    paths = [
        write_episode(tmp_path / f"{map_name}-{kind}-{minds}", map_name, seed, EpisodeSpec(minds, kind))
        for map_name in ("paper", "house-a")
        for kind in KINDS
        for minds in MINDS
        for seed in range(len(TASKS) if kind == "tasks" else 1)
    ]
    paths.append(write_house_episode(tmp_path / "house", rooms=5, items=3, seed=2, people=3))
    for path in paths:
        load_scenario(str(path))
