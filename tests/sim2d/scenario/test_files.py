"""Maps and scenarios load with validation whose errors name the file, the entry and what
is wrong."""

from __future__ import annotations

from pathlib import Path

import pytest

from sim2d.errors import ScenarioError
from sim2d.scenario.maps import SCENARIO_DIR, load_map
from sim2d.scenario.scenario import load_scenario, scenario_names

PAPER_MAP = (SCENARIO_DIR / "paper.map.toml").read_text()
PAPER_1 = (SCENARIO_DIR / "paper-1.toml").read_text()


def test_every_bundled_scenario_loads() -> None:
    names = scenario_names()
    assert {
        "paper-1",
        "paper-2",
        "paper-3",
        "paper-robot",
        "paper-robot-decline",
        "paper-tidy",
        "sally-anne",
        "food-trucks",
    } <= set(names)
    for name in names:
        scenario = load_scenario(name)
        assert scenario.name == name


def test_paper_map_matches_the_paper() -> None:
    game_map = load_map("paper")
    assert [r.id for r in game_map.regions] == ["P1", "S1", "S2", "P2", "E", "O"]
    joins = {frozenset(d.joins) for d in game_map.doors}
    assert joins == {
        frozenset(p) for p in [("P1", "S1"), ("S1", "S2"), ("S2", "P2"), ("S1", "E"), ("S2", "E"), ("E", "O")]
    }
    sees = {game_map.region_of[c]: set(v) for c, v in game_map.sees.items() if c in game_map.region_of}
    assert sees == {
        "P1": {"P1", "S1"},
        "S1": {"P1", "S1"},
        "S2": {"S2", "P2"},
        "P2": {"S2", "P2"},
        "E": set(),
        "O": set(),
    }
    assert game_map.region_of[game_map.homes["robot"]] == "E"


def _broken_map(tmp_path: Path, old: str, new: str) -> ScenarioError:
    assert old in PAPER_MAP, old
    path = tmp_path / "broken.map.toml"
    path.write_text(PAPER_MAP.replace(old, new, 1))
    with pytest.raises(ScenarioError) as caught:
        load_map(str(path))
    assert str(path) in str(caught.value), "the error should name the file"
    return caught.value


@pytest.mark.parametrize(
    ("old", "new", "entry", "problem"),
    [
        ('joins = ["P1", "S1"]', 'joins = ["P1", "S9"]', "doors[0] 'P1-S1'", "unknown room 'S9'"),
        ("cell = [3, 9]", "cell = [3, 5]", "doors[0] 'P1-S1'", "door not on a wall shared by P1 and S1"),
        (
            "cell = [1, 9]\nplay = true",
            "cell = [3, 10]\nplay = true",
            "locations[0] 'P1'",
            "item spot (3, 10) is in a wall",
        ),
        ('kind = "playground"', 'kind = "garden"', "regions[0] 'P1'", "unknown kind 'garden'"),
        ("rects = [[6, 0, 3, 3]]", "rects = [[6, 0, 3, 2]]", "doors[5] 'E-O'", "does not touch 'O'"),
        ('from = ["E"]', 'from = ["Attic"]', "visibility[2]", "unknown room 'Attic'"),
        ("robot = [7, 5]", "robot = [3, 5]", "homes.robot", "home cell (3, 5) is not walkable"),
    ],
)
def test_broken_map_names_entry(tmp_path: Path, old: str, new: str, entry: str, problem: str) -> None:
    err = _broken_map(tmp_path, old, new)
    assert err.entry == entry and problem in err.problem, f"expected {entry}: {problem}; got {err}"


def test_unreachable_room_is_named(tmp_path: Path) -> None:
    text = PAPER_MAP.replace('[[doors]]\nid = "E-O"\ncell = [7, 3]\njoins = ["E", "O"]\n', "")
    path = tmp_path / "island.map.toml"
    path.write_text(text)
    with pytest.raises(ScenarioError, match="unreachable") as caught:
        load_map(str(path))
    assert "'O'" in caught.value.problem and str(path) in str(caught.value)


def _broken_scenario(tmp_path: Path, old: str, new: str) -> ScenarioError:
    assert old in PAPER_1, old
    path = tmp_path / "broken.toml"
    path.write_text(
        PAPER_1.replace(old, new, 1).replace('map = "paper"', f'map = "{SCENARIO_DIR / "paper.map.toml"}"')
    )
    with pytest.raises(ScenarioError) as caught:
        load_scenario(str(path))
    assert str(path) in str(caught.value)
    return caught.value


@pytest.mark.parametrize(
    ("old", "new", "entry", "problem"),
    [
        (
            '{ do = "enter", region = "S1", label = "1" }',
            '{ do = "enter", region = "S7", label = "1" }',
            "agents[0] 'A1'.script[1]",
            "unknown room 'S7'",
        ),
        (
            '{ do = "drop", label = "2" }',
            '{ do = "jump" }',
            "agents[0] 'A1'.script[3]",
            "unknown step do = 'jump'",
        ),
        (
            'until = "A2:swapped"',
            'until = "A2:never"',
            "agents[0] 'A1'.script[6]",
            "no agent 'A2' step labelled 'never'",
        ),
        (
            '{ do = "take", item = "skate" }',
            '{ do = "take", item = "kite" }',
            "agents[1] 'A2'.script[3]",
            "unknown item 'kite'",
        ),
        ('at = "A1"', 'at = "attic"', "items[0] 'skate'", "'at' must be a location"),
        ('kind = "robot"', 'kind = "drone"', "agents[2] 'robot'", "expected kind 'person' or 'robot'"),
        ('robot = "observe"', 'robot = "maybe"', "robot", "expected 'act' or 'observe'"),
        (
            'id = "A1"',
            'id = "A1"\nerrand = 10',
            "agents[0] 'A1'",
            "task jobs (errand, move, wait, tell, knows, believes, overlooks) are for autonomous people",
        ),
        (
            'id = "A1"',
            'id = "A1"\nmove_after = 2.5',
            "agents[0] 'A1'",
            "expected move_after = a number of ticks",
        ),
        ('id = "A1"', 'id = "A1"\nknows = "ball"', "agents[0] 'A1'", "expected knows = [item, ...]"),
        ('id = "A1"', 'id = "A1"\nerrand = -1', "agents[0] 'A1'", "expected errand = a number of ticks >= 0"),
        ('id = "A1"', 'id = "A1"\nmove = ["ball"]', "agents[0] 'A1'", "expected move = [item, location]"),
        (
            'id = "A1"',
            'id = "A1"\nmove = ["ball", "attic"]',
            "agents[0] 'A1'",
            "move: unknown location 'attic'",
        ),
    ],
)
def test_broken_scenario_names_entry(tmp_path: Path, old: str, new: str, entry: str, problem: str) -> None:
    err = _broken_scenario(tmp_path, old, new)
    assert err.entry == entry and problem in err.problem, f"expected {entry}: {problem}; got {err}"


def test_toml_syntax_error_names_the_file(tmp_path: Path) -> None:
    path = tmp_path / "bad.toml"
    path.write_text('name = "x"\nmap = [unclosed\n')
    with pytest.raises(ScenarioError, match="not valid TOML") as caught:
        load_scenario(str(path))
    assert caught.value.path == path


def test_missing_scenario_is_named() -> None:
    with pytest.raises(ScenarioError, match="scenario 'paper-99': not bundled; known: .*paper-1"):
        load_scenario("paper-99")


def test_missing_scenario_file_is_named(tmp_path: Path) -> None:
    with pytest.raises(ScenarioError, match="no such file"):
        load_scenario(str(tmp_path / "nosuch.toml"))
