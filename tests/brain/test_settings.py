"""Settings from files and ``--set NAME=VALUE``: what is unknown or badly typed is named,
and the settings a run wrote read back to the same."""

from __future__ import annotations

from pathlib import Path

import pytest

from brain.errors import SettingsError
from brain.settings import ModelSettings, RobotSettings, Settings, load_settings, settings_toml


def test_defaults_then_file_then_overrides(tmp_path: Path) -> None:
    path = tmp_path / "s.toml"
    path.write_text('[model]\nbeta = 3\nbelief_model = "point"\n\n[robot]\nattempts = 4\n')
    settings = load_settings(path, ["beta=4.5", "robot.belief_threshold=0.7"])
    assert settings.model == ModelSettings(beta=4.5, belief_model="point")
    assert settings.robot == RobotSettings(attempts=4, belief_threshold=0.7)
    assert load_settings() == Settings()


def test_written_settings_read_back_the_same(tmp_path: Path) -> None:
    settings = Settings(ModelSettings(delta=1e-9, belief_update="paper"), RobotSettings(attempts=3))
    path = tmp_path / "settings.toml"
    path.write_text(settings_toml(settings))
    assert load_settings(path) == settings


@pytest.mark.parametrize(
    ("override", "message"),
    [
        ("betta=2", "unknown setting 'betta'; known: model.r"),
        ("beta=fast", "model.beta: expected float, got 'fast'"),
        ("attempts=2.5", "robot.attempts: expected int, got 2.5"),
        ("beta", "expected NAME=VALUE, got 'beta'"),
        ("belief_model=certain", "belief_model='certain'"),
        ("hazard=1.5", "hazard=1.5"),
    ],
)
def test_bad_overrides_are_named(override: str, message: str) -> None:
    with pytest.raises(SettingsError, match=message.replace("(", r"\(").replace(".", r"\.")):
        load_settings(None, [override])


def test_bad_files_are_named(tmp_path: Path) -> None:
    path = tmp_path / "s.toml"
    path.write_text("[modle]\nbeta = 3\n")
    with pytest.raises(SettingsError, match=r"s\.toml: unknown table \[modle\]"):
        load_settings(path)
    path.write_text("[model]\nbeta = \n")
    with pytest.raises(SettingsError, match=r"s\.toml"):
        load_settings(path)
    with pytest.raises(SettingsError, match="missing.toml"):
        load_settings(tmp_path / "missing.toml")


def test_infer_takes_settings_and_writes_them(tmp_path: Path) -> None:
    import subprocess
    import sys

    from support import toyroom_run

    run = toyroom_run(tmp_path / "run", "sally-anne", "--no-live", "--robot", "observe")
    assert 'belief_model = "graded"' in (run / "settings.toml").read_text()
    result = subprocess.run(
        [sys.executable, "-m", "bridge", "infer", str(run / "trace.jsonl"), "--out", str(tmp_path / "graded")]
        + ["--set", "belief_model=point"],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert result.returncode == 0, result.stderr
    assert 'belief_model = "point"' in (tmp_path / "graded" / "settings.toml").read_text()
    graded, point = (run / "mind.csv").read_text(), (tmp_path / "graded" / "mind.csv").read_text()
    assert point != graded, "the graded model inferred exactly what the point model did"


def test_infer_on_a_recording_reproduces_its_run(tmp_path: Path) -> None:
    """The brain's settings travel with the recording (MCAP metadata; the settings.toml
    beside trace.jsonl), so ``toyroom infer`` gives the run's mind.csv without being told."""
    import subprocess
    import sys

    from support import toyroom_run

    mcap = tmp_path / "run.mcap"
    run = toyroom_run(tmp_path / "run", "sally-anne", "--no-live", "--set", "beta=3", "--record", str(mcap))
    for source, name in ((mcap, "from-mcap"), (run / "trace.jsonl", "from-trace")):
        result = subprocess.run(
            [sys.executable, "-m", "bridge", "infer", str(source), "--out", str(tmp_path / name)],
            capture_output=True,
            text=True,
            timeout=120,
        )
        assert result.returncode == 0, result.stderr
        assert "using the settings recorded with the run" in result.stdout, result.stdout
        used = (tmp_path / name / "settings.toml").read_text()
        assert "beta = 3.0" in used, f"{name}: settings.toml says\n{used}"
        assert (tmp_path / name / "mind.csv").read_text() == (run / "mind.csv").read_text(), (
            f"{name}: infer did not reproduce the run's mind.csv"
        )
