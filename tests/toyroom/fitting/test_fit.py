"""``toyroom fit`` on real recordings (engine and brain over loopback Zenoh): a fitted
``settings.toml``, the folds and the model comparison; bad input named."""

from __future__ import annotations

import json
import tomllib
from pathlib import Path

import pytest
from support import toyroom_fit as fit


def test_fit_writes_settings_folds_and_the_comparison(recordings: list[Path], tmp_path: Path) -> None:
    out = tmp_path / "fit"
    result = fit(
        *recordings,
        "--params",
        "beta",
        "--grid",
        "beta=0.5,2",
        "--models",
        "graded,truebelief",
        "--folds",
        "3",
        "--out",
        out,
    )
    assert result.returncode == 0, result.stderr
    summary = json.loads((out / "fit.json").read_text())
    assert set(summary["ranking"]) == {"graded", "truebelief"}
    graded = summary["models"]["graded"]
    assert len(graded["folds"]) == 3 and all(f["actions"] > 0 for f in graded["folds"]), graded["folds"]
    assert graded["fitted"]["beta"] in (0.5, 2.0)
    per_action = graded["held_out_per_action"]
    assert per_action["lo"] <= per_action["mean"] <= per_action["hi"] < 0, per_action
    fitted = tomllib.loads((out / "settings.toml").read_text())
    assert fitted["model"]["beta"] == graded["fitted"]["beta"], "settings.toml holds the first model's fit"
    report = (out / "report.md").read_text()
    assert "| graded |" in report and "| truebelief |" in report and "toyroom fit" in report
    assert (out / "folds.csv").read_text().count("\n") == 1 + 2 * 3


def test_fit_names_bad_input(recordings: list[Path], tmp_path: Path) -> None:
    unknown = fit(*recordings, "--params", "gamma", "--out", tmp_path / "a")
    assert unknown.returncode == 2 and "'gamma'" in unknown.stderr, unknown.stderr
    broken = tmp_path / "broken.jsonl"
    broken.write_text("not json\n")
    bad = fit(recordings[0], broken, "--params", "beta", "--folds", "2", "--out", tmp_path / "b")
    assert bad.returncode == 2 and "broken.jsonl:1" in bad.stderr, bad.stderr
    missing = fit(recordings[0], tmp_path / "nope.jsonl", "--folds", "2", "--out", tmp_path / "c")
    assert missing.returncode == 2 and "nope.jsonl: no such recording" in missing.stderr, missing.stderr
    model = fit(*recordings, "--models", "graded,oracle", "--folds", "2", "--out", tmp_path / "d")
    assert model.returncode == 2 and "oracle" in model.stderr, model.stderr


@pytest.mark.sweep  # Ray starts its own cluster: a minute, beyond make test's budget
def test_fit_on_ray_finds_what_worker_processes_find(recordings: list[Path], tmp_path: Path) -> None:
    args = ("--params", "beta", "--grid", "beta=0.5,2", "--models", "graded,motion", "--folds", "3")
    local = fit(*recordings, *args, "--out", tmp_path / "local")
    ray = fit(*recordings, *args, "--backend", "ray", "--out", tmp_path / "ray")
    assert local.returncode == 0 and ray.returncode == 0, local.stderr[-2000:] + ray.stderr[-2000:]
    a, b = (json.loads((tmp_path / d / "fit.json").read_text())["models"] for d in ("local", "ray"))
    for model in ("graded", "motion"):
        assert a[model]["held_out_per_action"] == b[model]["held_out_per_action"], (model, a[model], b[model])


def test_a_fit_to_a_cut_recording_says_so_in_its_report(recordings: list[Path], tmp_path: Path) -> None:
    whole = recordings[0].read_bytes()
    cut = tmp_path / "cut.jsonl"
    cut.write_bytes(whole[: len(whole) * 2 // 3])  # a copy that stopped mid-line
    out = tmp_path / "fit"
    result = fit(cut, *recordings[1:], "--params", "beta", "--grid", "beta=2", "--folds", "2", "--out", out)
    assert result.returncode == 0, result.stderr
    report = (out / "report.md").read_text()
    assert "The recording was cut off" in report and "cut.jsonl" in report, (
        f"expected the report to say that cut.jsonl was cut off and what was kept, got:\n{report[:1500]}"
    )
    summary = json.loads((out / "fit.json").read_text())
    assert summary["recordings_not_whole"], "fit.json names no cut recording"


def test_folds_default_to_what_the_recordings_allow_and_one_fold_is_refused(
    recordings: list[Path], tmp_path: Path
) -> None:
    """Issue 55: with 3 recordings ``--folds`` (5 by default) becomes 3, and says so; ``--folds 1``
    was a Python traceback."""
    one = fit(*recordings, "--folds", "1", "--out", tmp_path / "one")
    assert one.returncode == 2 and "expected a whole number >= 2, got 1" in one.stderr, one.stderr
    assert "Traceback" not in one.stderr, one.stderr
    out = tmp_path / "three"
    three = fit(*recordings, "--params", "beta", "--grid", "beta=2", "--models", "graded", "--out", out)
    assert three.returncode == 0, three.stderr[-2000:]
    assert "3 recordings, so 3-fold cross-validation (not 5)" in three.stdout, three.stdout[:500]
    assert len(json.loads((out / "fit.json").read_text())["models"]["graded"]["folds"]) == 3
    alone = fit(recordings[0], "--params", "beta", "--out", tmp_path / "alone")
    assert alone.returncode == 2 and "at least 2 recordings, got 1" in alone.stderr, alone.stderr
