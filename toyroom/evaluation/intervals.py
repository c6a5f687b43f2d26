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
from .scores import metric_names

RESAMPLES = 1000
METRICS = metric_names(interval=True)
"""The metrics given a paired bootstrap interval (:class:`~toyroom.evaluation.scores.Scores`)."""


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
        resamples: how many bootstrap resamples of the episodes.
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
    if not names or not per_episode[names[0]]:
        return {}, {}
    points, draws = _mean_draws(per_episode, seed, resamples)
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


def _mean_draws(
    per_episode: Mapping[str, Sequence[tuple[float, int]]], seed: int, resamples: int
) -> tuple[dict[str, float | None], dict[str, list[float | None]]]:
    """Per name, the pooled mean ``sum / count`` over all episodes, and over each of
    ``resamples`` resamples of the episodes (the same ones for every name, by ``seed``)."""
    names = list(per_episode)
    n = len(per_episode[names[0]])
    arrays = {name: np.array(per_episode[name], dtype=np.float64).reshape(n, 2) for name in names}
    picks = np.random.default_rng(seed).integers(0, n, size=(resamples, n))

    def mean(values: np.ndarray) -> float | None:
        return float(values[:, 0].sum() / values[:, 1].sum()) if values[:, 1].sum() > 0 else None

    points = {name: mean(arrays[name]) for name in names}
    return points, {name: [mean(arrays[name][p]) for p in picks] for name in names}


def _cut(base: float | None, value: float | None) -> float | None:
    """``(base - value) / base``: the share of ``base`` that ``value`` cuts."""
    return None if base is None or value is None or base <= 0 else (base - value) / base


def _share(base: float | None, value: float | None, oracle: float | None) -> float | None:
    """``(base - value) / (base - oracle)``: the share of the oracle's cut (only when it cuts)."""
    if base is None or value is None or oracle is None or base - oracle <= 0:
        return None
    return (base - value) / (base - oracle)


def cuts(
    per_episode: Mapping[str, Sequence[tuple[float, int]]],
    seed: int,
    base: str,
    oracle: str | None = None,
    resamples: int = RESAMPLES,
) -> dict[str, dict[str, dict[str, float | None]]]:
    """Per name other than ``base`` (the robot observing), ``{cut, share_of_oracle}`` of the
    pooled means (each episode's ``(sum, count)``, as :func:`pooled_means`), each ``{mean, lo,
    hi}`` with a bootstrap 95% interval paired by episode: ``cut``, ``(base - name) / base``;
    ``share_of_oracle``, ``(base - name) / (base - oracle)``, when ``oracle`` ran and its cut is
    positive (else ``None``; a resample in which the oracle cuts nothing is left out of the
    interval)."""
    names = list(per_episode)
    if base not in per_episode or not per_episode[base]:
        return {}
    points, draws = _mean_draws(per_episode, seed, resamples)
    oracles = draws.get(oracle or "", [None] * resamples)
    out: dict[str, dict[str, dict[str, float | None]]] = {}
    for name in (n for n in names if n != base):
        pairs = list(zip(draws[base], draws[name], strict=True))
        share = _share(points[base], points[name], points.get(oracle or ""))
        out[name] = {
            "cut": _interval(_cut(points[base], points[name]), [_cut(b, v) for b, v in pairs]),
            "share_of_oracle": _interval(
                share, [_share(b, v, o) for (b, v), o in zip(pairs, oracles, strict=True)]
            ),
        }
    return out
