"""The grid search of ``toyroom fit``: every (model, grid point, recording) evaluated once,
in worker processes, with a progress bar; then each model's table cross-validated.

A *model* is an observer and settings overrides (:data:`MODELS`): the graded default, the
paper's point beliefs, belief-space planning, ``truebelief`` and a no-cost model (every
step free, so the path is no evidence of the goal). Each is fitted on the same grid (less a
parameter the model pins) and compared by held-out log-likelihood per action.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping, Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np

from bridge.recording.trace import Trace, read_trace
from protocol import Observer

from ..settings import ModelSettings
from .crossval import FloatArray, IntArray
from .evidence import Evidence, episode_evidence
from .grid import Point, apply, points

MODELS: dict[str, tuple[Observer, dict[str, object]]] = {
    "graded": (Observer.BTOM, {}),
    "point": (Observer.BTOM, {"belief_model": "point"}),
    "belief-planning": (Observer.BTOM, {"person_planner": "belief"}),
    Observer.TRUEBELIEF.value: (Observer.TRUEBELIEF, {}),
    "nocost": (Observer.BTOM, {"step_cost": 0.0}),
}
"""The models ``toyroom fit`` can compare: observer and the settings it pins."""
DEFAULT_MODELS = ("graded", "point", Observer.TRUEBELIEF.value, "nocost")
NO_ACTION_MODEL = (Observer.PERCEPTONLY.value,)
"""Observers without a model of actions: they give decisions no likelihood to compare."""


@dataclass(frozen=True)
class Table:
    """One model's search: its grid points and ``ll (P, E)``, ``actions (E,)``."""

    model: str
    points: list[Point]
    ll: FloatArray
    actions: IntArray


def model_grid(name: str, grid: Mapping[str, Sequence[float]]) -> dict[str, Sequence[float]]:
    """The grid of model ``name``: ``grid`` less what the model pins."""
    _, pinned = MODELS[name]
    return {k: v for k, v in grid.items() if k not in pinned}


def model_settings(name: str, base: ModelSettings, point: Mapping[str, float]) -> ModelSettings:
    """``base`` with model ``name``'s pinned settings and the point's values."""
    _, pinned = MODELS[name]
    return apply(dataclasses.replace(base, **pinned), point)  # type: ignore[arg-type]


@lru_cache(maxsize=64)
def _trace(path: str) -> Trace:
    return read_trace(Path(path))


def _evaluate(job: tuple[str, str, ModelSettings]) -> Evidence:
    path, observer, settings = job
    return episode_evidence(_trace(path), settings, Observer(observer))


def search(
    traces: Sequence[Path],
    models: Sequence[str],
    grid: Mapping[str, Sequence[float]],
    base: ModelSettings,
    workers: int = 2,
    progress: bool = True,
) -> list[Table]:
    """Evaluate every model at every point of its grid on every recording."""
    jobs, index = [], []
    for name in models:
        observer, _ = MODELS[name]
        for p, point in enumerate(points(model_grid(name, grid))):
            settings = model_settings(name, base, point)
            for e, path in enumerate(traces):
                jobs.append((str(path), observer.value, settings))
                index.append((name, p, e))
    results = _run(jobs, workers, progress)
    tables = {name: _empty_table(name, points(model_grid(name, grid)), len(traces)) for name in models}
    for (name, p, e), evidence in zip(index, results, strict=True):
        tables[name].ll[p, e] = evidence.log_likelihood
        tables[name].actions[e] = evidence.actions
    return [tables[name] for name in models]


def _empty_table(name: str, grid_points: list[Point], episodes: int) -> Table:
    return Table(
        name, grid_points, np.zeros((len(grid_points), episodes)), np.zeros(episodes, dtype=np.int64)
    )


def _run(jobs: list[tuple[str, str, ModelSettings]], workers: int, progress: bool) -> list[Evidence]:
    from rich.progress import Progress

    results: list[Evidence] = []
    with Progress(disable=not progress, transient=False) as bar:
        task = bar.add_task("fitting", total=len(jobs))
        if workers <= 1:
            for job in jobs:
                results.append(_evaluate(job))
                bar.advance(task)
            return results
        with ProcessPoolExecutor(max_workers=workers) as pool:
            for evidence in pool.map(_evaluate, jobs, chunksize=1):
                results.append(evidence)
                bar.advance(task)
    return results
