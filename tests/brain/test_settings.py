"""Settings from files and ``--set NAME=VALUE``: what is unknown or badly typed is named,
and the settings a run wrote read back to the same."""

from __future__ import annotations

import dataclasses
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
        [
            sys.executable,
            "-m",
            "toyroom",
            "infer",
            str(run / "trace.jsonl"),
            "--out",
            str(tmp_path / "graded"),
        ]
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
            [sys.executable, "-m", "toyroom", "infer", str(source), "--out", str(tmp_path / name)],
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


FLOAT_SETTINGS = [
    (section, f.name)
    for section, cls in (("model", ModelSettings), ("robot", RobotSettings))
    for f in dataclasses.fields(cls)
    if f.type in ("float", float)
]


@pytest.mark.parametrize(("section", "name"), FLOAT_SETTINGS)
@pytest.mark.parametrize("value", ["nan", "inf", "-inf", "1e308"])
def test_every_float_setting_is_finite_and_bounded(section: str, name: str, value: str) -> None:
    """Issue 49, item 3: a value that would make the model's numbers non-finite (NaN, an
    infinity, or one so large that a product of it overflows float64) is refused at start,
    naming the setting, its value and the bound."""
    with pytest.raises(SettingsError) as caught:
        load_settings(None, [f"{section}.{name}={value}"])
    message = str(caught.value)
    assert f"{name}=" in message and "allowed" in message and "\n" not in message, (
        f"expected one line naming {name} and what is allowed, got {message!r}"
    )


def test_a_settings_file_with_nan_or_deep_nesting_is_one_line(tmp_path: Path) -> None:
    """Issue 49, item 7: a settings file of NaN, or nested too deep for tomllib, is one line
    naming the file (no traceback)."""
    path = tmp_path / "s.toml"
    path.write_text("[model]\nbeta = nan\n")
    with pytest.raises(SettingsError, match=r"beta=nan \(allowed: a finite number"):
        load_settings(path)
    path.write_text("x = " + "[" * 100_000 + "]" * 100_000 + "\n")
    with pytest.raises(SettingsError) as caught:
        load_settings(path)
    message = str(caught.value)
    assert message.startswith(f"{path}: ") and "\n" not in message, (
        f"expected one line naming the file, got {message!r}"
    )


def test_check_settings_refuses_a_beta_that_overflows(tmp_path: Path) -> None:
    """Issue 49, item 3: ``--set beta=1e308`` (which made 39,013 NaN in mind.csv while the run
    exited 0) is refused by ``python -m brain check-settings`` (what ``toyroom run`` asks
    before it starts any process): exit 2 and one line naming the bound and why."""
    import subprocess
    import sys

    result = subprocess.run(
        [sys.executable, "-m", "brain", "check-settings", "--set", "beta=1e308"],
        capture_output=True,
        text=True,
        timeout=120,  # a Python start and an import: seconds, generous for a loaded machine
    )
    lines = result.stderr.strip().splitlines()
    assert result.returncode == 2 and len(lines) == 1, (
        f"expected exit 2 and one line, got {result.returncode}: {result.stderr!r}"
    )
    assert "beta=1e+308" in lines[0] and "1e6" in lines[0], f"expected the bound named, got {lines[0]!r}"


def test_a_former_name_is_read_as_the_new_one_with_a_warning(
    tmp_path: Path, caplog: pytest.LogCaptureFixture
) -> None:
    path = tmp_path / "old.toml"
    path.write_text("[model]\nforget = 0.01\n")
    for settings in (
        load_settings(path),
        load_settings(None, ["forget=0.01"]),
        load_settings(None, ["model.forget=0.01"]),
    ):
        assert settings.model == ModelSettings(forget_per_s=0.01), (
            f"expected forget read as forget_per_s=0.01, got forget_per_s={settings.model.forget_per_s}"
        )
    warnings = [r.getMessage() for r in caplog.records if r.levelname == "WARNING"]
    assert len(warnings) == 3, f"expected one warning per use of the former name, got {warnings}"
    assert all("'forget_per_s'" in w and "\n" not in w for w in warnings), (
        f"expected one line naming forget_per_s, got {warnings}"
    )


def test_a_setting_given_by_both_its_names_is_refused(tmp_path: Path) -> None:
    path = tmp_path / "both.toml"
    path.write_text("[model]\nforget = 0.01\nforget_per_s = 0.02\n")
    with pytest.raises(SettingsError, match=r"both\.toml: model\.forget_per_s is set twice"):
        load_settings(path)
