"""The studies (``studies/``) run: their numbers are in the docs, for people; no number is
asserted here beyond what each study is for."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
from support import STUDIES, study


def test_compare_models_runs(tmp_path: Path) -> None:
    out = tmp_path / "compare.json"
    result = subprocess.run(
        [sys.executable, str(STUDIES / "compare_models.py"), "--json", str(out)],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert result.returncode == 0, result.stderr
    numbers = json.loads(out.read_text())
    assert numbers["models"] == ["graded", "point"], numbers["models"]
    early = numbers["rows"]["S1 steps 0-2: P(false belief about the ball), online, max"]
    assert early[0] < early[1], f"graded should flag ignorance less than point does: {early}"


@pytest.mark.sweep  # the study end to end: a minute of CPU and more (make test's budget)
def test_time_view_runs() -> None:
    result = subprocess.run(
        [sys.executable, str(STUDIES / "time_view.py")], capture_output=True, text=True, timeout=300
    )
    assert result.returncode == 0, result.stderr
    assert "frame, median" in result.stdout


@pytest.mark.sweep  # an evaluation run and split by process: a minute of CPU (make test's budget)
def test_eval_cpu_splits_a_runs_cpu_by_process() -> None:
    rows = study("split_eval_cpu").main(seed=1, episodes=1)
    assert [row["run"] for row in rows] == ["btom-observe", "btom-act-tom"], rows
    for row in rows:
        for part in ("engine_cpu_s", "brain_cpu_s", "evaluator_cpu_s"):
            assert float(row[part]) > 0.05, f"{row['run']}: {part} should be measured, got {row[part]}"
        assert float(row["brain_cpu_s"]) > float(row["engine_cpu_s"]), (
            f"the brain infers, the engine steps: {row}"
        )


def test_food_truck_paths_prints_every_path_for_both_desire_models() -> None:
    result = subprocess.run(
        [sys.executable, str(STUDIES / "food_truck_paths.py")], capture_output=True, text=True, timeout=300
    )
    assert result.returncode == 0, result.stderr
    rows = [line for line in result.stdout.splitlines() if line.startswith("| ") and "---" not in line][1:]
    assert len(rows) == 16, f"expected 8 paths x 2 desire models, got {len(rows)} rows:\n{result.stdout}"
    arrival = [r for r in rows if "on arrival" in r]
    assert all("0.50 / 0.50" in r for r in arrival), f"read on arrival, L and M should tie:\n{arrival}"
