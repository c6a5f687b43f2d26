"""``--autonomy NAME=VALUE``: the same generated episode with one setting of its people
changed, every other line as drawn, and a bad setting named before anything is written."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from protocol import EpisodeKind, EpisodeSpec, Minds
from sim2d.errors import ScenarioError
from sim2d.generation.episodes import write_episode
from sim2d.generation.overrides import parse_override, with_autonomy
from sim2d.scenario.scenario import load_scenario


def test_an_override_replaces_the_drawn_setting_and_nothing_else(tmp_path: Path) -> None:
    drawn = write_episode(tmp_path / "drawn", "house-a", 11013, EpisodeSpec(Minds.RICH, EpisodeKind.TASKS))
    changed = write_episode(
        tmp_path / "changed",
        "house-a",
        11013,
        EpisodeSpec(Minds.RICH, EpisodeKind.TASKS, autonomy=("replan_lag=[100000, 100000]", "miss=0.3")),
    )
    before, after = load_scenario(str(drawn)).autonomy, load_scenario(str(changed)).autonomy
    assert after.replan_lag == (100000, 100000) and after.miss == 0.3, after
    assert before.miss != 0.3, f"the test needs a drawn miss other than 0.3, got {before.miss}"
    old = {line for line in drawn.read_text().splitlines() if not line.startswith(("miss =", "replan_lag ="))}
    new = {
        line for line in changed.read_text().splitlines() if not line.startswith(("miss =", "replan_lag ="))
    }
    assert old == new, f"lines other than the overridden ones changed: {sorted(old ^ new)}"


@pytest.mark.parametrize(
    ("text", "says"),
    [
        ("nope=1", "unknown autonomy setting 'nope'"),
        ("miss=[", "is not a TOML value"),
        ("miss", "NAME=VALUE"),
        ("=0.1", "NAME=VALUE"),
    ],
)
def test_a_malformed_override_is_named(text: str, says: str) -> None:
    with pytest.raises(ValueError, match=says):
        parse_override(text)


def test_an_override_the_table_cannot_take_is_refused_and_nothing_written(tmp_path: Path) -> None:
    with pytest.raises(ScenarioError, match=r"miss = 2\.0"):
        write_episode(tmp_path, "paper", 1, EpisodeSpec(autonomy=("miss=2",)))
    assert not (tmp_path / "gen-paper-s1.toml").exists(), "a refused episode was written"
    with pytest.raises(ScenarioError, match="tick pairs"):
        with_autonomy(
            '[autonomy]\nswitch = 0.1\n\n[[items]]\nid = "ball"\n', {"replan_lag": "[5]"}, tmp_path / "x.toml"
        )


def test_the_generate_command_names_a_bad_override(tmp_path: Path) -> None:
    made = subprocess.run(
        [sys.executable, "-m", "sim2d", "generate", "--autonomy", "miss=2", "--out", str(tmp_path)],
        capture_output=True,
        text=True,
        check=False,
    )
    assert made.returncode == 2 and "miss = 2.0" in made.stderr, (made.returncode, made.stderr[-500:])
