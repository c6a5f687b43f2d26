"""Why graded desires agree with desire ratings as they do: on a synthetic-ratings study kept
with ``python studies/rate_synthetic_people.py --out DIR``, each desire model's smoothed estimates
at the generating settings against the ratings and against the people's true utilities,
broken down by how the estimate is read and by which goals are rated.

For graded desires and one favourite (at the study's beta and hazard), over every ``utility``
question (the mean rating of each):

- ``rating ~ utility`` and ``rating ~ P(most wanted)``: Pearson r of the ratings with the
  estimate read as the posterior mean utility on the goal's scale, or as P(most wanted);
- ``truth ~ utility``: r of the true utility on the goal's scale (no rater noise) with it;
- ``top truth ~ utility`` and ``others truth ~ utility``: the same over the true favourite's
  rows only, and over the other goals' rows only (are the levels below the top read?);
- ``favourite found``: how often the goal the estimate wants most is the true favourite.

    python studies/diagnose_ratings.py DIR [--json FILE]
"""

from __future__ import annotations

import argparse
import dataclasses
import json
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from bridge.recording.trace import read_trace
from toyroom.fitting.correlation import pearson
from toyroom.fitting.judged import goal_scale, predictions
from toyroom.fitting.judgments import load_judgments


def diagnose(directory: Path) -> dict[str, dict[str, float]]:
    """The breakdown (see the module docstring) of the study kept in ``directory``."""
    kept = json.loads((directory / "truths.json").read_text(encoding="utf-8"))
    study, truths = kept["study"], kept["truths"]
    paths = sorted((directory / "recordings").glob("*.jsonl"))
    traces = [read_trace(p) for p in paths]
    judged = [
        j
        for j in load_judgments(directory / "ratings.csv", traces, [p.stem for p in paths])
        if j.quantity == "utility"
    ]
    base = dataclasses.replace(ModelSettings(), beta=study["beta"], hazard=study["hazard"])
    low, high = goal_scale(base, len(traces[0].info.scene.items))
    truth = np.array(
        [_true(truths[paths[j.episode].stem], j.person, j.tick, j.index[0], low, high) for j in judged]
    )
    top = np.array([_true_top(truths[paths[j.episode].stem], j.person, j.tick) == j.index[0] for j in judged])
    values = np.array([j.value for j in judged])
    out = {}
    for model in ("graded", "favourite"):
        settings = dataclasses.replace(base, desire_model=model)
        wanted, most = np.full(len(judged), np.nan), np.full(len(judged), np.nan)
        for e, trace in enumerate(traces):
            rows = [n for n, j in enumerate(judged) if j.episode == e]
            tracker = MindTracker(trace.info.scene, settings)
            for state, events in trace:
                tracker.observe(state, events)
            wanted[rows] = predictions(tracker, [judged[n] for n in rows])
            as_desire = [dataclasses.replace(judged[n], quantity="desire") for n in rows]
            most[rows] = predictions(tracker, as_desire)
        out[model] = {
            "rating ~ utility": pearson(wanted, values),
            "rating ~ P(most wanted)": pearson(most, values),
            "truth ~ utility": pearson(wanted, truth),
            "top truth ~ utility": pearson(wanted[top], truth[top]),
            "others truth ~ utility": pearson(wanted[~top], truth[~top]),
            "favourite found": _found(wanted, top, judged),
        }
    return out


def _true(truth: dict, person: str, tick: int, goal: int, low: np.ndarray, high: np.ndarray) -> float:
    u = np.array(_vector(truth, person, tick))
    return float(((u - low) / (high - low))[goal])


def _vector(truth: dict, person: str, tick: int) -> list[float]:
    changes = truth["favourites"][person]
    now = [goal for at, goal in changes if at <= tick] or [changes[0][1]]
    return truth["utilities"][now[-1]]


def _true_top(truth: dict, person: str, tick: int) -> int:
    return int(np.argmax(_vector(truth, person, tick)))


def _found(wanted: np.ndarray, top: np.ndarray, judged: Sequence) -> float:
    """The share of questions (episode, tick, person) whose most wanted goal by the estimate
    is the true favourite."""
    groups: dict[tuple[int, int, str], list[int]] = {}
    for n, j in enumerate(judged):
        groups.setdefault((j.episode, j.tick, j.person), []).append(n)
    hits = [
        top[rows][int(np.argmax(wanted[rows]))] for rows in groups.values() if np.isfinite(wanted[rows]).all()
    ]
    return float(np.mean(hits)) if hits else float("nan")


def main(argv: Sequence[str] | None = None) -> dict[str, dict[str, float]]:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("directory", type=Path, help="a study kept by synthetic_ratings.py --out")
    parser.add_argument("--json", type=Path, help="also write the numbers here")
    args = parser.parse_args(argv)
    numbers = diagnose(args.directory)
    for model, rows in numbers.items():
        print(model + ": " + "; ".join(f"{k} {v:.4f}" for k, v in rows.items()))
    if args.json:
        args.json.write_text(json.dumps(numbers, indent=2), encoding="utf-8")
    return numbers


if __name__ == "__main__":
    main()
