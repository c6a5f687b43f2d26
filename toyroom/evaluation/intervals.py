"""Bootstrap 95% confidence intervals of the evaluation's metrics, paired by episode.

Every observer is scored on the same episodes, so one resample of episode indices (with
replacement) serves all of them: the intervals of two observers, and of their difference,
come from the same resamples (a paired bootstrap). Pooled metrics (F1 from summed counts)
are recomputed on each resample. Pure functions over per-episode counts.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from .metrics import Counts

RESAMPLES = 1000
METRICS = (
    "belief_tv",
    "preference_accuracy",
    "false_belief_f1",
    "goal_false_belief_f1",
    "knowable_false_belief_f1",
    "revealed_detection",
    "revealed_detection_any",
    "brier",
    "log_loss",
    "brier_skill",
    "nested_belief_accuracy",
    "nested_first_order_accuracy",
    "nested_gain",
)


def _pooled(counts: Sequence[Counts], picks: np.ndarray) -> dict[str, float | None]:
    total = Counts()
    for i in picks:
        total.add(counts[int(i)])
    return total.metrics()


def _minus(a: float | None, b: float | None) -> float | None:
    return a - b if a is not None and b is not None else None


def _interval(point: float | None, draws: list[float | None]) -> dict[str, float | None]:
    values = np.array([d for d in draws if d is not None], dtype=np.float64)
    if point is None or len(values) == 0:
        return {"mean": point, "lo": None, "hi": None}
    lo, hi = np.percentile(values, [2.5, 97.5])
    return {"mean": point, "lo": float(lo), "hi": float(hi)}


def intervals(
    per_episode: Mapping[str, Sequence[Counts]], seed: int, resamples: int = RESAMPLES
) -> tuple[dict[str, dict[str, dict[str, float | None]]], dict[str, dict[str, dict[str, float | None]]]]:
    """``(intervals, differences)``: per observer and metric ``{mean, lo, hi}``, and per
    observer other than the first (the model), the first's metric minus theirs, paired.

    Args:
        per_episode: observer -> its counts on each episode, in the same episode order.
        seed: the resamples' seed (the evaluation's, so the numbers repeat).
    """
    names = list(per_episode)
    n = len(per_episode[names[0]]) if names else 0
    if n == 0:
        return {}, {}
    rng = np.random.default_rng(seed)
    picks = [rng.integers(0, n, size=n) for _ in range(resamples)]
    everything = np.arange(n)
    points = {name: _pooled(per_episode[name], everything) for name in names}
    draws = {name: [_pooled(per_episode[name], p) for p in picks] for name in names}
    out = {
        name: {m: _interval(points[name][m], [d[m] for d in draws[name]]) for m in METRICS} for name in names
    }
    model = names[0]
    differences: dict[str, dict[str, dict[str, float | None]]] = {}
    for other in names[1:]:
        differences[other] = {}
        for m in METRICS:
            paired = [_minus(x[m], y[m]) for x, y in zip(draws[model], draws[other], strict=True)]
            differences[other][m] = _interval(_minus(points[model][m], points[other][m]), paired)
    return out, differences


def pooled_means(
    per_episode: Mapping[str, Sequence[tuple[float, int]]], seed: int, resamples: int = RESAMPLES
) -> tuple[dict[str, dict[str, float | None]], dict[str, dict[str, float | None]]]:
    """``(intervals, differences)`` of pooled means: per name, each episode's ``(sum, count)``
    (e.g. ticks to goal summed over its people, and how many), the mean ``sum / count`` over
    all episodes with a bootstrap 95% interval, and the first name's mean minus each other's,
    paired by episode (the same resamples)."""
    names = list(per_episode)
    n = len(per_episode[names[0]]) if names else 0
    if n == 0:
        return {}, {}
    arrays = {name: np.array(per_episode[name], dtype=np.float64).reshape(n, 2) for name in names}
    rng = np.random.default_rng(seed)
    picks = rng.integers(0, n, size=(resamples, n))

    def mean(values: np.ndarray) -> float | None:
        return float(values[:, 0].sum() / values[:, 1].sum()) if values[:, 1].sum() > 0 else None

    points = {name: mean(arrays[name]) for name in names}
    draws = {name: [mean(arrays[name][p]) for p in picks] for name in names}
    out = {name: _interval(points[name], draws[name]) for name in names}
    first = names[0]
    differences = {
        other: _interval(
            _minus(points[first], points[other]),
            [_minus(a, b) for a, b in zip(draws[first], draws[other], strict=True)],
        )
        for other in names[1:]
    }
    return out, differences
