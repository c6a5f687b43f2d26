"""``toyroom fit --judgments``: ratings made from the brain's own estimates at a known beta
(with noise) are fitted back to that beta, with Pearson r per quantity; a judgments file
naming what the recordings do not have is an error naming the line and the name."""

from __future__ import annotations

import csv
import dataclasses
import json
import tomllib
from pathlib import Path

import numpy as np
from support import toyroom_fit as fit

from brain.fitting.judgments import estimate_at
from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from bridge.recording.trace import read_trace

HEADER = ["episode", "tick", "person", "quantity", "target", "value"]


def ratings(recordings: list[Path], beta: float, path: Path, noise: float = 0.03) -> Path:
    """Every 20 ticks, each person's desire for every goal and belief about the first item
    at its likeliest place, as the graded brain at ``beta`` estimates them, plus noise."""
    rng = np.random.default_rng(0)
    with path.open("w", newline="") as handle:
        out = csv.writer(handle)
        out.writerow(HEADER)
        for recording in recordings:
            trace = read_trace(recording)
            tracker = MindTracker(trace.info.scene, dataclasses.replace(ModelSettings(), beta=beta))
            for state, events in trace:
                tracker.observe(state, events)
            items = [i.id for i in trace.info.scene.items]
            places = [loc.id for loc in trace.info.scene.locations]
            for tick in range(0, trace.ticks[-1][0].tick, 20):
                for person in tracker.people:
                    est = estimate_at(tracker, person, tick)
                    if est is None:
                        continue
                    rows = [("desire", g, est.preference[d]) for d, g in enumerate([*items, "out"])]
                    where = int(np.argmax(est.beliefs[0]))
                    rows.append(("belief", f"{items[0]}@{places[where]}", est.beliefs[0, where]))
                    for quantity, target, value in rows:
                        noisy = float(value) + rng.normal(0.0, noise)
                        out.writerow([trace.info.scenario, tick, person, quantity, target, f"{noisy:.5f}"])
    return path


def test_fit_to_judgments_finds_the_beta_that_made_them(recordings: list[Path], tmp_path: Path) -> None:
    judgments = ratings(recordings, 0.5, tmp_path / "judgments.csv")
    out = tmp_path / "fit"
    models = "graded,motion,perceptonly"
    args = ("--params", "beta", "--grid", "beta=0.5,8", "--models", models, "--folds", "3")
    result = fit(*recordings, *args, "--judgments", judgments, "--out", out)
    assert result.returncode == 0, result.stderr
    every = json.loads((out / "fit.json").read_text())["judgments"]
    assert set(every) == {"graded", "motion", "perceptonly"}, f"judged models: {set(every)}"
    assert every["motion"]["fitted"] == {} == every["perceptonly"]["fitted"], (
        "the baselines have no parameters"
    )
    for baseline in ("motion", "perceptonly"):
        r = every[baseline]["r"]["desire"]["mean"]
        assert r < every["graded"]["r"]["desire"]["mean"], (
            f"{baseline} desire r {r} beat the generating model"
        )
    judged = every["graded"]
    assert judged["fitted"] == {"beta": 0.5}, f"expected the generating beta 0.5, got {judged['fitted']}"
    assert set(judged["r"]) == {"belief", "desire"}
    for quantity, r in judged["r"].items():
        assert r["lo"] <= r["mean"] <= r["hi"] and r["mean"] > 0.8, f"held-out r of {quantity}: {r}"
    assert tomllib.loads((out / "settings.toml").read_text())["model"]["beta"] == 0.5
    assert "## Fit to judgments" in (out / "report.md").read_text()


def test_judgments_naming_what_is_not_there_are_errors(recordings: list[Path], tmp_path: Path) -> None:
    good = ["paper-1", "30", "A1", "desire", "ball", "0.5"]
    cases = {
        "person 'Z9' is not in episode paper-1": ["paper-1", "30", "Z9", "desire", "ball", "0.5"],
        "item 'kite' is unknown": ["paper-1", "30", "A1", "belief", "kite@S1", "0.5"],
        "location 'S9' is unknown": ["paper-1", "30", "A1", "belief", "ball@S9", "0.5"],
        "goal 'cake' is unknown": ["paper-1", "30", "A1", "desire", "cake", "0.5"],
        "episode 'paper-9' is no recording given": ["paper-9", "30", "A1", "desire", "ball", "0.5"],
        "quantity 'mood' is unknown": ["paper-1", "30", "A1", "mood", "ball", "0.5"],
        "tick 99999 is outside episode paper-1": ["paper-1", "99999", "A1", "desire", "ball", "0.5"],
        "value a number": ["paper-1", "30", "A1", "desire", "ball", "high"],
    }
    for expected, row in cases.items():
        path = tmp_path / "bad.csv"
        with path.open("w", newline="") as handle:
            csv.writer(handle).writerows([HEADER, good, row])
        result = fit(
            *recordings, "--params", "beta", "--folds", "2", "--judgments", path, "--out", tmp_path / "o"
        )
        assert result.returncode == 2, f"expected an error for {row}, got rc {result.returncode}"
        assert "bad.csv line 3" in result.stderr and expected in result.stderr, (
            f"expected {expected!r} at line 3, got: {result.stderr.strip()}"
        )
    headless = tmp_path / "headless.csv"
    headless.write_text("paper-1,30,A1,desire,ball,0.5\n")
    result = fit(
        *recordings, "--params", "beta", "--folds", "2", "--judgments", headless, "--out", tmp_path / "o"
    )
    assert result.returncode == 2 and "expected a header" in result.stderr, result.stderr
