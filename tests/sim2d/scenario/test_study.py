"""A scenario's ``[study]`` section (what ``toyroom play`` tells a participant and when their
episode ends): read into :class:`protocol.Study`, printed by ``python -m sim2d scene --study``,
and refused with a message naming the key when it is wrong."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from protocol import Goal, Study
from sim2d.errors import ScenarioError
from sim2d.scenario.maps import SCENARIO_DIR
from sim2d.scenario.scenario import load_scenario

ROBOT = (SCENARIO_DIR / "paper-robot.toml").read_text()
BASE = ROBOT[: ROBOT.index("[study]")].replace(
    'map = "paper"', f'map = "{(SCENARIO_DIR / "paper.map.toml").as_posix()}"'
)


def _load(tmp_path: Path, study: str) -> Study | None:
    path = tmp_path / "studied.toml"
    path.write_text(BASE + study)
    return load_scenario(str(path)).study


def test_paper_robot_asks_a1_to_get_the_skate_back_after_going_out() -> None:
    study = load_scenario("paper-robot").study
    assert study is not None and "Agent 1" in study.instructions and "skate" in study.goal, study
    assert study.reached == Goal(holds="skate", after="4"), study.reached
    assert study.time_limit == 400.0 and study.consent == "", study


def test_a_scenario_without_a_study_has_none() -> None:
    assert load_scenario("paper-1").study is None


@pytest.mark.parametrize(
    ("section", "where", "says"),
    [
        ('[study]\ngoal = "x"\nreward = 3\n', "study", "unknown field `reward`"),
        ('[study]\nreached = { holds = "skate", enters = "O" }\n', "study.reached", "exactly one of"),
        ("[study]\nreached = {}\n", "study.reached", "got none"),
        (
            '[study]\nreached = { holds = "kite" }\n',
            "study.reached.holds",
            "no item 'kite' (known: ball, skate)",
        ),
        ('[study]\nreached = { enters = "Attic" }\n', "study.reached.enters", "no region 'Attic'"),
        (
            '[study]\nreached = { holds = "skate", after = "99" }\n',
            "study.reached.after",
            "no step is labelled '99'",
        ),
        ("[study]\ntime_limit = 0\n", "study", "Expected `float` >= 0.0"),
        ("[study]\ninstructions = 4\n", "study", "Expected `str`, got `int`"),
    ],
)
def test_a_wrong_study_section_is_refused_naming_what_is_wrong(
    tmp_path: Path, section: str, where: str, says: str
) -> None:
    with pytest.raises(ScenarioError) as caught:
        _load(tmp_path, section)
    text = str(caught.value)
    assert where in text and says.split(" >=")[0] in text, f"expected '{where}' and '{says}' in: {text}"


def test_sim2d_scene_prints_the_study_beside_the_scene() -> None:
    result = subprocess.run(
        [sys.executable, "-m", "sim2d", "scene", "--scenario", "paper-robot", "--study"],
        capture_output=True, text=True, timeout=120, check=False,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    printed = json.loads(result.stdout)
    assert printed["scene"]["name"] == "paper" and printed["study"]["reached"]["holds"] == "skate", printed[
        "study"
    ]
