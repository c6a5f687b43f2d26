"""Fitting to judgments (``toyroom fit --judgments``): the grid point whose estimates
correlate best with people's ratings, cross-validated by episode.

A point's score on some episodes is the mean over kinds of judgment (a quantity, of the
online or the smoothed estimate: :attr:`Judgment.kind`) of the correlation between the
brain's estimates and the ratings of those episodes: Pearson's r on the raw ratings, and
Spearman's for ``rank`` (a rank is ordinal). Each fold is fitted on the others and its
episodes are predicted at that point; the held-out predictions of every fold together give
each kind's r, with a bootstrap 95% interval over episodes, and each model's difference from
the first model's, paired by episode (the same resampled episodes for both).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from protocol import Observer

from .crossval import FloatArray, IntArray
from .grid import Point, points
from .judged import predictions
from .judgments import Judgment
from .motion import MOTION, motion_predictions
from .search import MODELS, _trace, model_grid, model_settings

BOOTSTRAP = 1000


def pearson(x: FloatArray, y: FloatArray) -> float:
    """Pearson's r of the rows where both are numbers (``nan`` with fewer than 3 or no spread)."""
    ok = np.isfinite(x) & np.isfinite(y)
    if ok.sum() < 3 or np.std(x[ok]) == 0 or np.std(y[ok]) == 0:
        return float("nan")
    return float(np.corrcoef(x[ok], y[ok])[0, 1])


def undefined_because(x: FloatArray, y: FloatArray) -> str | None:
    """Why :func:`pearson` of ``x`` (estimates) and ``y`` (ratings) is ``nan``, in words for a
    report (``None``: it is a number)."""
    ok = np.isfinite(x) & np.isfinite(y)
    if ok.sum() < 3:
        unseen = int((np.isfinite(y) & ~np.isfinite(x)).sum())
        before = f"; {unseen} asked before the person was first seen (no estimate)" if unseen else ""
        return f"{int(ok.sum())} rated value(s) with an estimate, 3 needed{before}"
    if np.std(x[ok]) == 0:
        return "the model's estimates do not vary across the rated values"
    if np.std(y[ok]) == 0:
        return "the ratings do not vary"
    return None


def spearman(x: FloatArray, y: FloatArray) -> float:
    """Spearman's rank correlation of the rows where both are numbers (ties: mean ranks)."""
    from scipy.stats import rankdata

    ok = np.isfinite(x) & np.isfinite(y)
    return pearson(rankdata(x[ok]), rankdata(y[ok])) if ok.any() else float("nan")


def correlation(kind: str, x: FloatArray, y: FloatArray) -> float:
    """The correlation a kind of judgment is compared by: Spearman's for a rank, else Pearson's."""
    return spearman(x, y) if kind.endswith("rank") else pearson(x, y)


def score(pred: FloatArray, values: FloatArray, quantities: Sequence[str], rows: IntArray) -> float:
    """The mean over kinds of judgment of their correlation on ``rows`` (kinds without one
    left out)."""
    q = np.asarray(quantities)
    rs = [
        correlation(name, pred[rows][q[rows] == name], values[rows][q[rows] == name])
        for name in sorted(set(q[rows]))
    ]
    finite = [r for r in rs if np.isfinite(r)]
    return float(np.mean(finite)) if finite else float("-inf")


@dataclass(frozen=True)
class JudgedFit:
    """One model fitted to the judgments: the points, every fold's choice, each kind's
    held-out r with its interval, and the held-out predictions ``held (N,)``."""

    model: str
    points: list[Point]
    fold_points: list[int]
    fitted: Point
    r: dict[str, dict[str, Any]]
    held: FloatArray | None = None
    minus_first: dict[str, dict[str, Any]] | None = None
    """Each kind's ``r - r(first model)``, paired by episode (:func:`against_first`)."""


def fit_judgments(
    model: str,
    grid_points: list[Point],
    pred: FloatArray,
    judgments: Sequence[Judgment],
    parts: list[IntArray],
    seed: int = 0,
) -> JudgedFit:
    """Cross-validate ``pred (P, N)`` (each point's estimate of each judgment) by episode."""
    values = np.array([j.value for j in judgments])
    quantities = [j.kind for j in judgments]
    episode = np.array([j.episode for j in judgments])
    everything = np.arange(len(judgments))
    held = np.full(len(judgments), np.nan)
    chosen = []
    for part in parts:
        inside = np.isin(episode, part)
        train = everything[~inside]
        best = int(np.argmax([score(p, values, quantities, train) for p in pred]))
        held[inside] = pred[best, inside]
        chosen.append(best)
    best_all = int(np.argmax([score(p, values, quantities, everything) for p in pred]))
    r = _intervals(held, values, quantities, episode, seed)
    return JudgedFit(model, grid_points, chosen, grid_points[best_all], r, held)


def _intervals(
    held: FloatArray, values: FloatArray, quantities: Sequence[str], episode: IntArray, seed: int
) -> dict[str, dict[str, Any]]:
    """Each kind's r with a bootstrap 95% interval over episodes."""
    return paired_difference(held, None, values, quantities, episode, seed)


def paired_difference(
    held: FloatArray,
    other: FloatArray | None,
    values: FloatArray,
    kinds: Sequence[str],
    episode: IntArray,
    seed: int,
) -> dict[str, dict[str, Any]]:
    """Each kind's ``r(held) - r(other)`` (``r(held)`` when ``other`` is ``None``), with a
    bootstrap 95% interval over episodes, both predictions on the same resampled episodes."""
    rng = np.random.default_rng(seed)
    q = np.asarray(kinds)
    episodes = np.unique(episode)
    rows_of = {e: np.flatnonzero(episode == e) for e in episodes}

    def r(rows: IntArray, name: str) -> float:
        base = correlation(name, held[rows], values[rows])
        return base if other is None else base - correlation(name, other[rows], values[rows])

    out = {}
    for name in sorted(set(kinds)):
        mine = q == name
        draws = []
        for _ in range(BOOTSTRAP):
            rows = np.concatenate([rows_of[e] for e in rng.choice(episodes, size=len(episodes))])
            draws.append(r(rows[mine[rows]], name))
        finite = [d for d in draws if np.isfinite(d)]
        lo, hi = np.percentile(finite, [2.5, 97.5]) if finite else (float("nan"), float("nan"))
        rows = np.flatnonzero(mine)
        entry: dict[str, Any] = {"mean": r(rows, name), "lo": float(lo), "hi": float(hi)}
        entry["episodes"] = len(np.unique(episode[rows]))
        if not np.isfinite(entry["mean"]):
            entry["why"] = undefined_because(held[rows], values[rows])
        out[name] = entry
    return out


def against_first(fits: Sequence[JudgedFit], judgments: Sequence[Judgment], seed: int = 0) -> list[JudgedFit]:
    """``fits`` with every model after the first given its ``minus_first``: each kind's
    held-out r less the first model's, with a bootstrap 95% interval over episodes paired
    by episode."""
    if not fits or fits[0].held is None:
        return list(fits)
    values = np.array([j.value for j in judgments])
    kinds = [j.kind for j in judgments]
    episode = np.array([j.episode for j in judgments])
    first = fits[0].held
    return [fits[0]] + [
        dataclasses.replace(f, minus_first=paired_difference(f.held, first, values, kinds, episode, seed))
        if f.held is not None
        else f
        for f in fits[1:]
    ]


JudgedJob = tuple[str, str, ModelSettings, tuple[Judgment, ...]]


def _judged(job: JudgedJob) -> FloatArray:
    path, observer, settings, rows = job
    trace = _trace(path)
    if observer == MOTION:
        return motion_predictions(trace, rows)
    tracker = MindTracker(trace.info.scene, settings, observer=Observer(observer))
    for state, events in trace:
        tracker.observe(state, events)
    return predictions(tracker, rows)


def judged_search(
    traces: Sequence[Path],
    models: Sequence[str],
    grid: Mapping[str, Sequence[float]],
    base: ModelSettings,
    judgments: Sequence[Judgment],
    workers: int = 2,
    progress: bool = True,
) -> dict[str, tuple[list[Point], FloatArray]]:
    """Every model's estimate of every judgment at every point of its grid: ``(P, N)``."""
    from rich.progress import Progress

    by_episode = {e: [n for n, j in enumerate(judgments) if j.episode == e] for e in range(len(traces))}
    grids = {name: points(model_grid(name, grid, judged=True)) for name in models}
    jobs: list[JudgedJob] = []
    index: list[tuple[str, int, list[int]]] = []
    for name, grid_points in grids.items():
        observer = MODELS[name].observer
        for p, point in enumerate(grid_points):
            for e, path in enumerate(traces):
                if by_episode[e]:
                    mine = tuple(judgments[n] for n in by_episode[e])
                    jobs.append((str(path), observer, model_settings(name, base, point), mine))
                    index.append((name, p, by_episode[e]))
    out = {name: (g, np.full((len(g), len(judgments)), np.nan)) for name, g in grids.items()}
    with Progress(disable=not progress) as bar, ProcessPoolExecutor(max_workers=max(workers, 1)) as pool:
        task = bar.add_task("fitting to judgments", total=len(jobs))
        for (name, p, rows), pred in zip(index, pool.map(_judged, jobs, chunksize=1), strict=True):
            out[name][1][p, rows] = pred
            bar.advance(task)
    return out
