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
import pytest
from support import toyroom_fit as fit

from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from bridge.recording.trace import read_trace
from toyroom.fitting.judged import estimate_at, predictions
from toyroom.fitting.judgments import Judgment, load_judgments

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
    report = (out / "report.md").read_text()
    assert "## Fit to judgments" in report
    assert "ratings by raters not named (no participant column), of 3 recording(s)" in report, report
    likely = json.loads((out / "fit.json").read_text())["models"]["graded"]["fitted"]
    written = tomllib.loads((out / "settings-likelihood.toml").read_text())["model"]["beta"]
    assert written == likely["beta"], (
        f"settings-likelihood.toml has beta {written}, the likelihood fit {likely}"
    )
    assert "- `settings.toml`: graded at beta=0.5, from the fit to judgments" in report, report


def test_the_report_says_why_an_r_is_missing_and_when_one_recording_was_rated() -> None:
    """Issue 55: ``nan`` columns and one-episode intervals printed without a word."""
    from toyroom.fitting.correlation import undefined_because
    from toyroom.fitting.fit import _judgments_table

    nan = np.nan
    assert "2 rated value(s) with an estimate, 3 needed; 1 asked before the person was first seen" in str(
        undefined_because(np.array([0.1, 0.2, nan]), np.array([0.3, 0.4, 0.5]))
    )
    assert undefined_because(np.array([0.5, 0.5, 0.5]), np.array([0.1, 0.2, 0.3])) == (
        "the model's estimates do not vary across the rated values"
    )
    assert (
        undefined_because(np.array([0.1, 0.2, 0.3]), np.array([0.5, 0.5, 0.5])) == "the ratings do not vary"
    )
    assert undefined_because(np.array([0.1, 0.2, 0.3]), np.array([0.2, 0.1, 0.5])) is None
    judged = {
        "graded": {
            "fitted": {"beta": 4.0},
            "r": {
                "belief": {"mean": 0.7, "lo": 0.7, "hi": 0.7, "episodes": 1},
                "desire": {
                    "mean": None,
                    "lo": None,
                    "hi": None,
                    "episodes": 1,
                    "why": "the ratings do not vary",
                },
            },
        }
    }
    text = "\n".join(_judgments_table(judged, {"ratings": 40, "raters": 2, "episodes": 1}))
    assert "40 ratings by 2 raters, of 1 recording(s)" in text, text
    assert "- graded, desire: no r (the ratings do not vary)." in text, text
    assert "belief, desire: rated on one recording only" in text and "no interval" in text, text


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
        "goal 'kite' is unknown": ["paper-1", "30", "A1", "rank", "kite", "2"],
        "estimate 'later' is unknown": ["paper-1", "30", "A1", "utility", "ball", "0.5", "later"],
    }
    for expected, row in cases.items():
        path = tmp_path / "bad.csv"
        with path.open("w", newline="") as handle:
            csv.writer(handle).writerows([[*HEADER, "estimate"], [*good, ""], row + [""] * (7 - len(row))])
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


def _tracked(recording: Path, desire_model: str) -> MindTracker:
    trace = read_trace(recording)
    tracker = MindTracker(trace.info.scene, dataclasses.replace(ModelSettings(), desire_model=desire_model))
    for state, events in trace:
        tracker.observe(state, events)
    return tracker


def _goal_rows(tracker: MindTracker, person: str, tick: int, estimate: str) -> list[Judgment]:
    goals = len(tracker.scene.items) + 1
    return [
        Judgment(0, 0, tick, person, quantity, (g,), 0.0, estimate)
        for quantity in ("desire", "utility", "rank")
        for g in range(goals)
    ]


@pytest.mark.parametrize("desire_model", ["favourite", "graded"])
def test_smoothed_utility_and_rank_are_read_off_the_estimates(
    recordings: list[Path], desire_model: str
) -> None:
    tracker = _tracked(recordings[1], desire_model)
    person = tracker.people[0]
    steps = tracker.tracks[person].steps
    first, last = steps[0].tick, steps[-1].tick
    D = len(tracker.scene.items) + 1
    read = {
        (tick, estimate): predictions(tracker, _goal_rows(tracker, person, tick, estimate)).reshape(3, D)
        for tick in (first, last)
        for estimate in ("online", "smoothed")
    }
    for (tick, estimate), (desire, wanted, rank) in read.items():
        where = f"{desire_model} at tick {tick}, {estimate}"
        assert np.isclose(rank.sum(), D * (D + 1) / 2), (
            f"{where}: expected ranks summing to {D * (D + 1) / 2}, got {rank}"
        )
        assert ((wanted >= 0) & (wanted <= 1)).all(), f"{where}: utilities on the goals' scale, got {wanted}"
        assert np.argmin(rank) == np.argmax(wanted), (
            f"{where}: the most wanted goal ranks first: {wanted}, {rank}"
        )
        if desire_model == "favourite":
            assert np.allclose(wanted, desire), (
                f"{where}: one favourite's utility is P(most wanted): {wanted} vs {desire}"
            )
    assert np.allclose(read[(last, "smoothed")], read[(last, "online")]), (
        "at the last step smoothing is filtering"
    )
    assert not np.allclose(read[(first, "smoothed")], read[(first, "online")]), (
        f"at the first step the smoothed desire should know the rest of the path: {read[(first, 'smoothed')]}"
    )


def test_raters_are_averaged_and_extra_columns_read_past(recordings: list[Path], tmp_path: Path) -> None:
    path = tmp_path / "page.csv"
    with path.open("w", newline="") as handle:
        rows = [[*HEADER, "estimate", "participant", "question"]]
        rows += [
            ["paper-1", "30", "A1", "utility", "ball", v, "smoothed", f"p{n}", "q1"]
            for n, v in enumerate("153")
        ]
        rows += [["paper-1", "30", "A1", "utility", "ball", "7", "", "p0", "q2"]]
        rows += [["paper-1", "30", "A1", "rank", "out", "2", "online", "p0", "q3"]]
        csv.writer(handle).writerows(rows)
    traces = [read_trace(r) for r in recordings]
    judged = load_judgments(path, traces, [r.parent.name for r in recordings])
    got = [(j.kind, j.value, j.line) for j in judged]
    assert got == [("smoothed utility", 3.0, 2), ("utility", 7.0, 5), ("rank", 2.0, 6)], (
        f"expected three questions, the first the mean of its three ratings: {got}"
    )


def test_fit_to_smoothed_goal_ratings_compares_models_paired(recordings: list[Path], tmp_path: Path) -> None:
    path = tmp_path / "judgments.csv"
    with path.open("w", newline="") as handle:
        out = csv.writer(handle)
        out.writerow([*HEADER, "estimate"])
        for recording in recordings:
            tracker = _tracked(recording, "graded")
            episode = read_trace(recording).info.scenario
            for person in tracker.people:
                for tick in (tracker.ticks[len(tracker.ticks) // 3], tracker.ticks[-1]):
                    rows = _goal_rows(tracker, person, tick, "smoothed")
                    goals = [*(i.id for i in tracker.scene.items), "out"]
                    for j, value in zip(rows, predictions(tracker, rows), strict=True):
                        if j.quantity != "desire" and np.isfinite(value):
                            target = goals[j.index[0]]
                            out.writerow([episode, tick, person, j.quantity, target, value, "smoothed"])
    result = fit(
        *recordings,
        "--params",
        "beta",
        "--grid",
        "beta=2,3",
        "--models",
        "graded-desires,one-favourite",
        "--folds",
        "3",
        "--judgments",
        path,
        "--out",
        tmp_path / "fit",
    )
    assert result.returncode == 0, result.stderr
    judged = json.loads((tmp_path / "fit" / "fit.json").read_text())["judgments"]
    assert set(judged["graded-desires"]["r"]) == {"smoothed utility", "smoothed rank"}, judged[
        "graded-desires"
    ]["r"]
    assert judged["graded-desires"]["minus_first"] is None
    minus = judged["one-favourite"]["minus_first"]
    for kind in ("smoothed utility", "smoothed rank"):
        r = judged["graded-desires"]["r"][kind]
        assert r["mean"] > 0.95, (
            f"ratings that are graded desires' estimates at beta 2 should correlate: {kind} {r}"
        )
        d = minus[kind]
        assert d["lo"] <= d["mean"] <= d["hi"], f"{kind}: {d}"
        assert np.isclose(d["mean"], judged["one-favourite"]["r"][kind]["mean"] - r["mean"]), (kind, d)
