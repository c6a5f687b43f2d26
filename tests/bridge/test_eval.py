"""``toyroom eval`` end to end: metrics.json's shape, and the Ray backend (on a local Ray
instance, loopback only) giving the same metrics as the local one for the same seed."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest


def run_eval(out: Path, backend: str) -> dict:
    result = subprocess.run(
        [
            sys.executable,
            "-m",
            "bridge",
            "eval",
            "--episodes",
            "2",
            "--seed",
            "5",
            "--workers",
            "2",
            "--backend",
            backend,
            "--out",
            str(out),
        ],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert result.returncode == 0, result.stdout[-2000:] + result.stderr[-2000:]
    return json.loads((out / "metrics.json").read_text())


def test_eval_writes_every_metric_and_ray_agrees(tmp_path: Path) -> None:
    pytest.importorskip("ray")
    local = run_eval(tmp_path / "local", "local")
    assert local["episodes"] == 2 and local["seed"] == 5
    for observer in ("btom", "truebelief", "perceptonly"):
        assert set(local["observers"][observer]) == {
            "belief_tv",
            "preference_accuracy",
            "false_belief_precision",
            "false_belief_recall",
            "false_belief_f1",
        }
    assert set(local["robot"]) == {"with", "without"}
    assert local["observers"]["btom"]["belief_tv"] is not None
    assert (tmp_path / "local" / "report.md").read_text().startswith("# Evaluation: 2 episodes")
    ray = run_eval(tmp_path / "ray", "ray")
    # runs retried after a node crashed say something about the machine, not the brain
    retried = {"local": local.pop("failed_runs_retried"), "ray": ray.pop("failed_runs_retried")}
    assert ray == local, f"the Ray backend gave {ray}, the local one {local} (retried runs: {retried})"
