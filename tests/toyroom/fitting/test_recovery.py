"""Parameter recovery: people who act by the brain's own planner at beta 4 and hazard 0.02
(``toyroom eval --minds model``, recorded), then ``toyroom fit`` on the recordings finds beta,
and the generating model (graded beliefs) explains their actions better than truebelief.

Four short episodes pin beta down but the hazard only coarsely (of 0.001, 0.02 and 0.4 it
must pick 0.02; a grid of factor 2 steps needs docs/fitting.md's 40 episodes, where the whole
comparison is shown with intervals, the generating model first)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest
from support import toyroom_fit as fit


@pytest.mark.sweep  # a parameter's recovery over episodes: `make sweeps` (tests/tiers.py)
@pytest.mark.timeout(900)
def test_fit_recovers_the_planners_beta_and_hazard(tmp_path: Path) -> None:
    evaluation = subprocess.run(
        [sys.executable, "-m", "toyroom", "eval", "--episodes", "4", "--minds", "model"]
        + ["--set", "beta=4", "--set", "hazard=0.02", "--policies", "none", "--max-ticks", "800"]
        + ["--record", "--out", str(tmp_path / "eval")],
        capture_output=True,
        text=True,
        timeout=900,
    )
    assert evaluation.returncode == 0, evaluation.stderr[-3000:]
    recordings = sorted((tmp_path / "eval" / "recordings" / "omniscient-model-everyday").glob("*.mcap"))
    assert len(recordings) == 4, f"expected 4 recordings, got {recordings}"
    out = tmp_path / "fit"
    result = fit(
        *recordings,
        "--params",
        "beta,hazard",
        "--grid",
        "beta=1,4,16",
        "--grid",
        "hazard=0.001,0.02,0.4",
        "--models",
        "graded,truebelief,nocost",
        "--folds",
        "2",
        "--out",
        out,
    )
    assert result.returncode == 0, result.stderr
    summary = json.loads((out / "fit.json").read_text())
    fitted = summary["models"]["graded"]["fitted"]
    assert 3.0 <= fitted["beta"] <= 5.0, f"expected beta 4 within 25%, got {fitted}"
    assert 0.005 <= fitted["hazard"] <= 0.08, f"expected hazard 0.02 of 0.001, 0.02, 0.4, got {fitted}"
    ranking = summary["ranking"]
    assert ranking.index("graded") < ranking.index("truebelief"), (
        f"expected graded above truebelief: {ranking}"
    )
