"""The motion heuristic as a model to fit: on real recordings, people who walk to their
goals are better predicted by following their heading than by chance; ``toyroom fit``
compares it (and ``perceptonly``, on judgments only) next to the brain's models."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
from support import toyroom_fit as fit

from brain.settings import ModelSettings
from bridge.recording.trace import read_trace
from protocol import AgentKind
from toyroom.fitting.judgments import Judgment
from toyroom.fitting.motion import motion_evidence, motion_predictions


def test_following_the_heading_beats_chance(recordings: list[Path]) -> None:
    trace = read_trace(recordings[1])
    chance, heading, against = motion_evidence(
        trace,
        ModelSettings(),
        [{"beta": 0.0, "epsilon": 0.0}, {"beta": 3.0, "epsilon": 0.05}, {"beta": -3.0, "epsilon": 0.05}],
    )
    assert chance.actions == heading.actions > 10, (chance, heading)
    assert heading.log_likelihood > chance.log_likelihood > against.log_likelihood, (
        f"expected heading {heading.log_likelihood:.1f} > chance {chance.log_likelihood:.1f} > "
        f"walking away {against.log_likelihood:.1f}"
    )
    assert chance.log_likelihood < 0 and np.isfinite(against.log_likelihood)


def test_motion_desire_is_the_item_where_the_person_heads(recordings: list[Path]) -> None:
    trace = read_trace(recordings[1])
    scene = trace.info.scene
    person = next(a.id for a in scene.agents if a.kind is AgentKind.PERSON)
    last = trace.ticks[-1][0].tick
    goals = len(scene.items) + 1
    rows = [
        Judgment(n, 0, tick, person, "desire", (g,), 0.0)
        for n, (tick, g) in enumerate((t, g) for t in range(0, last, 25) for g in range(goals))
    ]
    desire = motion_predictions(trace, rows).reshape(-1, goals)
    seen = desire[np.isfinite(desire).all(axis=1)]
    assert len(seen) > 3, desire
    assert np.allclose(seen.sum(axis=1), 1.0), f"each tick's desires should sum to 1, got {seen.sum(axis=1)}"
    assert (seen.max(axis=1) == 1.0).any(), "somewhere the person heads for one goal"


def test_fit_compares_motion_and_perceptonly(recordings: list[Path], tmp_path: Path) -> None:
    out = tmp_path / "fit"
    models = "graded,motion,perceptonly"
    result = fit(
        *recordings,
        "--params",
        "beta,hazard",
        "--grid",
        "beta=0.5,3",
        "--grid",
        "hazard=0.01",
        "--models",
        models,
        "--folds",
        "3",
        "--out",
        out,
    )
    assert result.returncode == 0, result.stderr
    summary = json.loads((out / "fit.json").read_text())
    assert set(summary["ranking"]) == {"graded", "motion"}, "perceptonly has no model of actions"
    assert set(summary["models"]["motion"]["fitted"]) == {"beta"}, "the motion heuristic has no hazard"
    assert "compared on judgments only" in (out / "report.md").read_text()
    first = fit(*recordings, "--models", "motion,graded", "--folds", "3", "--out", tmp_path / "bad")
    assert first.returncode == 2 and "must be one of the brain's" in first.stderr, first.stderr
