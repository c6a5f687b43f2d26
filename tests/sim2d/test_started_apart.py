"""Issue 49, item 8: a scenario file runs with the nodes started apart. ``toyroom sim
--scenario my-house.toml`` then ``toyroom brain`` (the README's live view): the brain asks the
engine to reset to the scenario it plays, by the name its ``engine_info`` gives; before, sim2d
answered ``unknown_scenario: no scenario named 'my-house'`` and the brain exited 2."""

from __future__ import annotations

from pathlib import Path

from support import EngineProcess, run_brain

from protocol import ClockMode
from sim2d.engine import Engine
from sim2d.scenario.maps import SCENARIO_DIR


def _my_house(folder: Path) -> Path:
    """``sally-anne`` copied with its map into ``folder`` as ``my-house.toml`` (name ``my-house``)."""
    text = (SCENARIO_DIR / "sally-anne.toml").read_text()
    assert 'name = "sally-anne"' in text, "sally-anne.toml no longer names itself"
    path = folder / "my-house.toml"
    path.write_text(text.replace('name = "sally-anne"', 'name = "my-house"', 1))
    (folder / "sally-anne.map.toml").write_text((SCENARIO_DIR / "sally-anne.map.toml").read_text())
    return path


def test_a_reset_to_the_name_playing_resets_its_file(tmp_path: Path) -> None:
    engine = Engine(str(_my_house(tmp_path)))
    assert engine.info("w", ClockMode.LOCKSTEP).scenario == "my-house"
    result = engine.reset("my-house", seed=3)
    got = (engine.scenario.path, result.state.episode)
    assert got == (tmp_path / "my-house.toml", 1), f"expected episode 1 of my-house.toml, got {got}"


def test_a_brain_started_apart_runs_a_scenario_file(world: str, tmp_path: Path) -> None:
    path = _my_house(tmp_path)
    with EngineProcess(world, "--scenario", str(path)) as engine:
        brain = run_brain(world, "--out", str(tmp_path / "out"), "--robot", "observe")
        engine_output = engine.output()
    assert brain.returncode == 0, (
        f"expected the brain to finish (exit 0), got {brain.returncode}: {brain.stderr}\n"
        f"engine: {engine_output}"
    )
    assert (tmp_path / "out" / "mind.csv").stat().st_size > 0, "expected the brain's mind.csv written"
