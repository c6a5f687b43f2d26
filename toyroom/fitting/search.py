"""The grid search of ``toyroom fit``: every (model, grid point, recording) evaluated once,
in worker processes, with a progress bar; then each model's table cross-validated. The
points of one model that differ only in ``beta``, ``epsilon`` and ``hazard`` share one pass
over each recording (:mod:`toyroom.fitting.replay`).

A *model* is an observer and settings overrides (:data:`MODELS`): the graded default, the
paper's point beliefs, belief-space planning, ``truebelief``, a no-cost model (every step
free, so the path is no evidence of the goal), ``graded-desires`` and ``one-favourite`` (the
default with ``desire_model`` pinned to ``graded`` or ``favourite``), the motion heuristic
(:mod:`toyroom.fitting.motion`) and ``perceptonly`` (judgments only: it has no model of
actions). Each is fitted on the same grid (less a parameter the model pins or lacks) and
compared by held-out log-likelihood per action.
"""

from __future__ import annotations

import dataclasses
import tempfile
from collections.abc import Mapping, Sequence
from concurrent.futures import ProcessPoolExecutor
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

import numpy as np

from brain.settings import ModelSettings
from bridge.recording.trace import Trace, read_trace
from protocol import Observer

from .crossval import FloatArray, IntArray
from .evidence import Evidence, episode_evidence
from .grid import Point, apply, points
from .motion import MOTION, motion_evidence
from .replay import CHEAP, evidence_at_points


@dataclass(frozen=True)
class ModelSpec:
    """A model ``toyroom fit`` can compare.

    Attributes:
        observer: the brain's observer that runs it (an :class:`~protocol.Observer` value), or
            :data:`~toyroom.fitting.motion.MOTION` for the motion heuristic.
        pinned: the settings it fixes (left out of its grid).
        params: the only parameters it has (``None``: every setting).
        actions: whether it gives decisions a likelihood (``perceptonly`` does not: it is
            compared on judgments only).
        judged_params: whether its estimates of judged quantities depend on the grid.
    """

    observer: str
    pinned: Mapping[str, object] = dataclasses.field(default_factory=dict)
    params: tuple[str, ...] | None = None
    actions: bool = True
    judged_params: bool = True


MODELS: dict[str, ModelSpec] = {
    "graded": ModelSpec(Observer.BTOM.value),
    "point": ModelSpec(Observer.BTOM.value, {"belief_model": "point"}),
    "belief-planning": ModelSpec(Observer.BTOM.value, {"person_planner": "belief"}),
    Observer.TRUEBELIEF.value: ModelSpec(Observer.TRUEBELIEF.value),
    "nocost": ModelSpec(Observer.BTOM.value, {"step_cost": 0.0}),
    "graded-desires": ModelSpec(Observer.BTOM.value, {"desire_model": "graded"}),
    "one-favourite": ModelSpec(Observer.BTOM.value, {"desire_model": "favourite"}),
    MOTION: ModelSpec(MOTION, params=("beta", "epsilon"), judged_params=False),
    Observer.PERCEPTONLY.value: ModelSpec(Observer.PERCEPTONLY.value, actions=False, judged_params=False),
}
"""The models ``toyroom fit`` can compare."""
DEFAULT_MODELS = ("graded", "point", Observer.TRUEBELIEF.value, "nocost", MOTION, Observer.PERCEPTONLY.value)
BRAIN_MODELS = tuple(name for name, spec in MODELS.items() if spec.observer != MOTION and spec.actions)
"""The models whose fitted point is brain settings (``settings.toml``)."""


@dataclass(frozen=True)
class Table:
    """One model's search: its grid points and ``ll (P, E)``, ``actions (E,)``."""

    model: str
    points: list[Point]
    ll: FloatArray
    actions: IntArray


def model_grid(
    name: str, grid: Mapping[str, Sequence[float]], judged: bool = False
) -> dict[str, Sequence[float]]:
    """The grid of model ``name``: ``grid`` less what the model pins or does not have (none
    of it for a model whose judgments take no parameters, when ``judged``)."""
    spec = MODELS[name]
    if judged and not spec.judged_params:
        return {}
    return {
        k: v for k, v in grid.items() if k not in spec.pinned and (spec.params is None or k in spec.params)
    }


def model_settings(name: str, base: ModelSettings, point: Mapping[str, float]) -> ModelSettings:
    """``base`` with model ``name``'s pinned settings and the point's values."""
    return apply(dataclasses.replace(base, **MODELS[name].pinned), point)  # type: ignore[arg-type]


@lru_cache(maxsize=64)
def _trace(path: str) -> Trace:
    return read_trace(Path(path))


Job = tuple[str, str, ModelSettings, tuple[Point, ...]]
"""One recording under one model's settings, at several values of the cheap parameters."""


@lru_cache(maxsize=4)
def _shipped_trace(data: bytes, name: str) -> Trace:
    """A recording that came by value (a Ray task's), read once per worker process."""
    with tempfile.TemporaryDirectory(prefix="toyroom-fit-") as scratch:
        path = Path(scratch) / name
        path.write_bytes(data)
        return read_trace(path)


def evaluate_job(job: Job) -> list[Evidence]:
    """The evidence at each cheap point: one replayed pass when the model allows it
    (:mod:`toyroom.fitting.replay`), else one pass per point."""
    return _evidence(_trace(job[0]), job)


def evaluate_shipped(job: Job, recording: tuple[str, bytes]) -> list[Evidence]:
    """:func:`evaluate_job` with the recording by value, ``(its name, its bytes)``, instead of
    its path (a file of the driver's machine): a Ray task's."""
    name, data = recording
    return _evidence(_shipped_trace(data, name), job)


def _evidence(trace: Trace, job: Job) -> list[Evidence]:
    """The evidence of ``job`` at its cheap points on ``trace`` (its recording)."""
    _, observer, settings, cheap = job
    if observer == MOTION:
        return motion_evidence(trace, settings, cheap)
    fast = evidence_at_points(trace, settings, Observer(observer), cheap)
    if fast is not None:
        return fast
    return [episode_evidence(trace, apply(settings, point), Observer(observer)) for point in cheap]


def _grouped(grid_points: list[Point]) -> dict[tuple[tuple[str, float], ...], list[int]]:
    """The indices of ``grid_points`` by their values of the parameters that are not cheap."""
    groups: dict[tuple[tuple[str, float], ...], list[int]] = {}
    for p, point in enumerate(grid_points):
        key = tuple(sorted((k, v) for k, v in point.items() if k not in CHEAP))
        groups.setdefault(key, []).append(p)
    return groups


def search(
    traces: Sequence[Path],
    models: Sequence[str],
    grid: Mapping[str, Sequence[float]],
    base: ModelSettings,
    workers: int = 2,
    progress: bool = True,
    backend: str = "local",
    address: str | None = None,
) -> list[Table]:
    """Evaluate every model at every point of its grid on every recording (the points that
    differ only in :data:`~toyroom.fitting.replay.CHEAP` parameters in one job), in worker
    processes or as Ray tasks (``backend``; ``address``: the Ray cluster's, default
    ``RAY_ADDRESS``)."""
    jobs: list[Job] = []
    index: list[tuple[str, list[int], int]] = []
    for e, path in enumerate(traces):
        for name in models:
            observer = MODELS[name].observer
            grid_points = points(model_grid(name, grid))
            for key, members in _grouped(grid_points).items():
                settings = model_settings(name, base, dict(key))
                cheap = tuple({k: v for k, v in grid_points[p].items() if k in CHEAP} for p in members)
                jobs.append((str(path), observer, settings, cheap))
                index.append((name, members, e))
    results = _run(jobs, workers, progress, backend, address)
    tables = {name: _empty_table(name, points(model_grid(name, grid)), len(traces)) for name in models}
    for (name, members, e), evidence in zip(index, results, strict=True):
        for p, ev in zip(members, evidence, strict=True):
            tables[name].ll[p, e] = ev.log_likelihood
            tables[name].actions[e] = ev.actions
    return [tables[name] for name in models]


def _empty_table(name: str, grid_points: list[Point], episodes: int) -> Table:
    return Table(
        name, grid_points, np.zeros((len(grid_points), episodes)), np.zeros(episodes, dtype=np.int64)
    )


def _run(
    jobs: list[Job], workers: int, progress: bool, backend: str = "local", address: str | None = None
) -> list[list[Evidence]]:
    """Every job's evidence, in order, with a progress bar over (model, point, recording) runs:
    in worker processes, or as Ray tasks (``backend = "ray"``, :mod:`toyroom.evaluation.raybackend`)
    on the cluster at ``address``, each recording sent to the nodes by value."""
    from rich.progress import Progress

    results: list[list[Evidence]] = []
    with Progress(disable=not progress, transient=False) as bar:
        task = bar.add_task("fitting", total=sum(len(job[3]) for job in jobs))
        if backend == "ray":  # the bar counts jobs: Ray finishes them in any order
            from toyroom.evaluation.raybackend import run_with_ray

            bar.update(task, total=len(jobs))
            return run_with_ray(
                evaluate_shipped,
                jobs,
                workers,
                lambda n: bar.advance(task, n),
                address=address,
                shipped=lambda job: [job[0]],
            )
        if workers <= 1:
            for job in jobs:
                results.append(evaluate_job(job))
                bar.advance(task, len(job[3]))
            return results
        with ProcessPoolExecutor(max_workers=workers) as pool:
            for job, evidence in zip(jobs, pool.map(evaluate_job, jobs, chunksize=1), strict=True):
                results.append(evidence)
                bar.advance(task, len(job[3]))
    return results
