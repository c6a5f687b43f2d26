"""A morning (``toyroom generate --day D --morning FILE``) is checked strictly against the
household it would start a day of: each thing that does not fit is one line naming it, exit 2,
and no day is written (``python -m sim2d generate``, run in-process)."""

from __future__ import annotations

import json
import tomllib
from pathlib import Path
from typing import Any

import pytest

from sim2d.__main__ import generate_main
from sim2d.scenario.maps import SCENARIO_DIR, load_map

PAPER = [loc.id for loc in load_map(str(SCENARIO_DIR / "paper.map.toml")).locations]


def good_morning(tmp_path: Path) -> dict[str, Any]:
    """The end of a day of household ``gen-paper-s7``: its items where they began, everyone
    sure of them, A1 wanting the first item and A2 going out."""
    day1 = tmp_path / "day1"
    assert generate_main(["--map", "paper", "--seed", "7", "--day", "1", "--out", str(day1)]) == 0
    data = tomllib.loads(next(day1.glob("*.toml")).read_text())
    items = {item["id"]: item["at"] for item in data["items"]}
    people = [a["id"] for a in data["agents"] if a.get("kind") == "person"]
    first = sorted(items)[0]
    return {
        "items": items,
        "beliefs": {p: dict(items) for p in people},
        "favourites": {people[0]: first, **{p: "out" for p in people[1:]}},
        "household": "gen-paper-s7",
        "map": "paper",
    }


def day2(tmp_path: Path, morning: dict[str, Any], seed: int = 7) -> int:
    path = tmp_path / "morning.json"
    path.write_text(json.dumps(morning))
    argv = ["--map", "paper", "--seed", str(seed), "--day", "2", "--morning", str(path)]
    return generate_main([*argv, "--out", str(tmp_path / "day2")])


def broken(morning: dict[str, Any], how: str) -> dict[str, Any]:
    items, people = sorted(morning["items"]), sorted(morning["favourites"])
    changed = json.loads(json.dumps(morning))
    if how == "item at NOWHERE":
        changed["items"][items[0]] = "NOWHERE"
    elif how == "unknown item":
        changed["items"]["kite"] = PAPER[0]
    elif how == "missing item":
        del changed["items"][items[-1]]
    elif how == "unknown person":
        changed["favourites"]["Z9"] = "out"
    elif how == "missing person":
        del changed["favourites"][people[-1]]
    elif how == "belief in an unknown place":
        changed["beliefs"][people[0]][items[0]] = "ATTIC"
    elif how == "unknown favourite":
        changed["favourites"][people[0]] = "kite"
    elif how == "no household or map":
        del changed["household"], changed["map"]
    elif how == "another map":
        changed["map"] = "house-a"
    return changed


CASES = {
    "item at NOWHERE": "puts item '{item}' at 'NOWHERE', not a place of map 'paper'",
    "unknown item": "names unknown items 'kite'",
    "missing item": "names no place for items '{last}'",
    "unknown person": "names unknown people 'Z9'",
    "missing person": "names no favourite for '{person}'",
    "belief in an unknown place": "believes item '{item}' is at 'ATTIC', not a place of map 'paper'",
    "unknown favourite": "favourite 'kite' is not a goal of the household",
    "no household or map": (
        'names no household and map (a morning written before they were required): add "household": '
        '"gen-paper-s7", "map": "paper"'
    ),
    "another map": "not of household 'gen-paper-s7' on map 'paper'",
}


@pytest.mark.parametrize("how", list(CASES))
def test_a_morning_that_does_not_fit_is_one_line(
    how: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    morning = good_morning(tmp_path)
    capsys.readouterr()
    code = day2(tmp_path, broken(morning, how))
    err = capsys.readouterr().err
    items, people = sorted(morning["items"]), sorted(morning["favourites"])
    said = CASES[how].format(item=items[0], last=items[-1], person=people[-1])
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1, f"{how}: expected exit 2 and one line, got {code}: {err!r}"
    assert lines[0].startswith("python -m sim2d generate: --morning ") and said in lines[0], (
        f"{how}: expected a line naming {said!r}, got {lines[0]!r}"
    )
    assert not list((tmp_path / "day2").glob("*.toml")), f"{how}: expected no day written"


def test_another_households_morning_is_refused_and_its_own_is_taken(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    morning = good_morning(tmp_path)
    capsys.readouterr()
    assert day2(tmp_path, morning, seed=8) == 2
    err = capsys.readouterr().err
    assert (
        "is the end of a day of household 'gen-paper-s7' on map 'paper', not of household 'gen-paper-s8'"
        in err
    ), err
    assert day2(tmp_path, morning) == 0, capsys.readouterr().err
    written = tomllib.loads(next((tmp_path / "day2").glob("*.toml")).read_text())
    assert written["household"] == {"id": "gen-paper-s7", "day": 2}
