"""Former keys of ``[autonomy]`` (``forget``, now ``forget_per_tick``): episodes written
before the rename load the same, with a one-line warning naming the new key."""

from __future__ import annotations

from pathlib import Path

import pytest

from protocol import EpisodeKind, EpisodeSpec, Minds
from sim2d.errors import ScenarioError
from sim2d.generation.episodes import write_episode
from sim2d.generation.overrides import parse_override
from sim2d.scenario.scenario import load_scenario

RICH_TASKS = EpisodeSpec(Minds.RICH, EpisodeKind.TASKS)
"""Rich minds, a task episode."""


def test_an_episode_with_the_former_key_loads_the_same(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    new = write_episode(tmp_path / "new", "house-a", 11013, RICH_TASKS)
    text = new.read_text()
    assert "\nforget_per_tick = " in text, "expected a rich episode to draw forget_per_tick"
    old = new.parent / "old.toml"  # beside its map
    old.write_text(text.replace("\nforget_per_tick = ", "\nforget = "))
    before, after = load_scenario(str(new)).autonomy, load_scenario(str(old)).autonomy
    assert after == before, f"expected the same autonomy under the former key, got {after} for {before}"
    warnings = [r.getMessage() for r in caplog.records if r.levelname == "WARNING"]
    assert len(warnings) == 1 and "'forget_per_tick'" in warnings[0], (
        f"expected one warning naming forget_per_tick, got {warnings}"
    )


def test_both_keys_at_once_are_refused(tmp_path: Path) -> None:
    path = write_episode(tmp_path / "ep", "house-a", 11013, RICH_TASKS)
    path.write_text(path.read_text().replace("\nforget_per_tick = ", "\nforget = 0.001\nforget_per_tick = "))
    with pytest.raises(ScenarioError, match="forget_per_tick is set twice"):
        load_scenario(str(path))


def test_an_override_by_the_former_key_sets_the_new_one() -> None:
    got = parse_override("forget=0.001")
    assert got == ("forget_per_tick", "0.001"), f"expected ('forget_per_tick', '0.001'), got {got}"
