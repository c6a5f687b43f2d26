"""The continuous refinement of ``toyroom fit --refine``: the first model's parameters by
maximum marginal likelihood over every recording, with a bounded derivative-free optimiser
(:func:`scipy.optimize.minimize`), started from the grid's best point.

The objective is the log-likelihood of every decision in every recording (the sum of
:class:`~toyroom.fitting.evidence.Evidence`), one tracker pass per recording and point, in
worker processes. It has no analytic gradient, and it is not smooth everywhere: lapse rows
split, merge and are pruned at thresholds (:mod:`brain.model.person.lapses`), so a finite-difference
gradient (L-BFGS-B) can be thrown by a kink a step wide. Powell's method (the default) needs
no gradient, searches one direction at a time with a bracketing line search inside the bounds,
and so moves far from a coarse grid's point in few evaluations; ``nelder-mead`` (bounded
since scipy 1.7) is the alternative. The result is the best point evaluated (the grid's
included): on a rough objective the optimiser may end beside a better point it passed.

Each parameter is searched in ``[0, 1]``, mapped onto its :data:`BOUNDS` linearly or, for
rates and scales, on a log scale (so a step is a factor, and recovering a rate "within a
factor" is what the tolerance means). The bounds lie inside the range
:class:`~brain.settings.ModelSettings` allows: open ends are closed a little inside, a lower
end of 0 becomes a floor below which the parameter makes no difference the data can show,
and an unbounded end a cap (a grid value of 0, below a log floor, is kept only when no point the
optimiser tries beats it)."""

from __future__ import annotations

import math
import time
from collections.abc import Mapping, Sequence
from concurrent.futures import Executor, ProcessPoolExecutor
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import numpy as np

from brain.errors import SettingsError
from brain.settings import ModelSettings, current_name

from .grid import Point
from .replay import CHEAP
from .search import MODELS, Job, evaluate_job, model_settings


@dataclass(frozen=True)
class Bound:
    """A parameter's search range ``[low, high]``, on a log scale when ``log``."""

    low: float
    high: float
    log: bool = True

    def to_unit(self, value: float) -> float:
        """``value`` (clipped into the range) as a coordinate in ``[0, 1]``."""
        v = min(max(value, self.low), self.high)
        if self.log:
            return (math.log(v) - math.log(self.low)) / (math.log(self.high) - math.log(self.low))
        return (v - self.low) / (self.high - self.low)

    def from_unit(self, u: float) -> float:
        """The value at coordinate ``u`` (clipped into ``[0, 1]``; the ends exactly)."""
        if u <= 0.0 or u >= 1.0:
            return self.low if u <= 0.0 else self.high
        if self.log:
            return math.exp(math.log(self.low) + u * (math.log(self.high) - math.log(self.low)))
        return self.low + u * (self.high - self.low)


BOUNDS: dict[str, Bound] = {
    "beta": Bound(0.05, 64.0),  # beta >= 0
    "hazard": Bound(1e-4, 0.5),  # 0 <= hazard < 1 (per decision)
    "epsilon": Bound(1e-5, 0.5),  # 0 <= epsilon < 1
    "r": Bound(0.1, 1000.0),  # r > 0
    "delta": Bound(1e-6, 0.2),  # 0 <= delta < 0.5
    "ignorance": Bound(0.0, 1.0, log=False),  # 0 <= ignorance <= 1
    "step_cost": Bound(0.0, 10.0, log=False),  # any; the grid's range and beyond
    "miss": Bound(1e-3, 0.5),  # 0 <= miss < 1 (per item coming into view); above 0.5 a lapse
    # would be likelier than a sight, and its row would outweigh the noticed one from birth
    "hearsay_per_s": Bound(1e-3, 10.0),  # >= 0 (per second per pair)
    "forget_per_s": Bound(1e-5, 0.1),  # >= 0 (per second)
}
"""Each fittable parameter's range for the optimiser (see the module docstring); every
parameter of :data:`toyroom.fitting.grid.GRIDS` has one. ``--bounds NAME=LO,HI`` replaces one."""
METHODS = ("powell", "nelder-mead")


def parse_bounds(names: Sequence[str], overrides: Sequence[str] = ()) -> dict[str, Bound]:
    """The bounds of ``names``, with ``NAME=LO,HI`` overrides (the scale kept).

    Raises:
        SettingsError: naming an override that is not ``NAME=LO,HI`` with ``LO < HI`` of a
            parameter in ``names``, or a range the settings do not allow."""
    bounds = {n: BOUNDS[n] for n in names}
    for text in overrides:
        name, sep, values = text.partition("=")
        name = current_name(name.strip())
        parts = values.split(",")
        if not sep or name not in bounds or len(parts) != 2:
            raise SettingsError(
                f"--bounds {text!r}: expected NAME=LO,HI with NAME one of {', '.join(bounds)}"
            )
        try:
            low, high = (float(p) for p in parts)
        except ValueError:
            raise SettingsError(f"--bounds {text!r}: LO and HI must be numbers") from None
        scale = bounds[name].log
        if not low < high or (scale and low <= 0):
            raise SettingsError(
                f"--bounds {text!r}: need LO < HI{' and LO > 0 (log scale)' if scale else ''}"
            )
        bounds[name] = Bound(low, high, scale)
    for name, bound in bounds.items():
        for value in (bound.low, bound.high):
            try:
                ModelSettings(**{name: value})  # type: ignore[arg-type]
            except ValueError as err:
                raise SettingsError(f"bounds of {name}: {err}") from None
    return bounds


@dataclass(frozen=True)
class Refinement:
    """The optimiser's result for ``model``: the grid's best point and its log-likelihood
    (``start``), the best ``point`` evaluated and its ``log_likelihood`` (natural log, every
    recording, ``actions`` decisions), how many points were evaluated (one tracker pass
    over every recording each), whether the optimiser reported convergence, and its words."""

    model: str
    method: str
    start: Point
    start_log_likelihood: float
    point: Point
    log_likelihood: float
    actions: int
    evaluations: int
    converged: bool
    message: str
    seconds: float
    bounds: dict[str, tuple[float, float]]

    def as_json(self) -> dict[str, Any]:
        return asdict(self)


class Objective:
    """Minus the log-likelihood of every recording at a point of ``[0, 1]^d`` (cached by
    point), each recording one job in ``pool``."""

    def __init__(
        self,
        traces: Sequence[Path],
        model: str,
        base: ModelSettings,
        bounds: Mapping[str, Bound],
        pool: Executor | None,
    ) -> None:
        self.traces, self.model, self.base, self.bounds, self.pool = traces, model, base, bounds, pool
        self.cache: dict[tuple[float, ...], tuple[float, int]] = {}

    def point(self, u: Sequence[float] | np.ndarray) -> Point:
        """The parameter values at coordinates ``u`` (rounded to 6 significant digits)."""
        return {
            n: float(f"{b.from_unit(float(x)):.6g}") for (n, b), x in zip(self.bounds.items(), u, strict=True)
        }

    def evidence(self, point: Point) -> tuple[float, int]:
        """``(log-likelihood, decisions)`` over every recording at ``point``."""
        key = tuple(point[n] for n in self.bounds)
        if key not in self.cache:
            cheap = {k: v for k, v in point.items() if k in CHEAP}
            settings = model_settings(
                self.model, self.base, {k: v for k, v in point.items() if k not in CHEAP}
            )
            observer = MODELS[self.model].observer
            jobs: list[Job] = [(str(path), observer, settings, (cheap,)) for path in self.traces]
            results = list(self.pool.map(evaluate_job, jobs) if self.pool else map(evaluate_job, jobs))
            self.cache[key] = (
                float(sum(r[0].log_likelihood for r in results)),
                int(sum(r[0].actions for r in results)),
            )
        return self.cache[key]

    def __call__(self, u: np.ndarray) -> float:
        ll = self.evidence(self.point(u))[0]
        return -ll if math.isfinite(ll) else 1e300


def refine(
    traces: Sequence[Path],
    model: str,
    start: Point,
    base: ModelSettings,
    bounds: Mapping[str, Bound],
    method: str = "powell",
    max_evals: int = 200,
    workers: int = 2,
) -> Refinement:
    """Maximise the log-likelihood of ``traces`` under ``model`` over the parameters of
    ``bounds``, from ``start`` (the grid's best point); ``max_evals`` caps the points tried.

    Raises:
        SettingsError: for an unknown ``method`` or a model without a likelihood of actions."""
    from scipy.optimize import minimize

    if method not in METHODS:
        raise SettingsError(f"unknown optimiser {method!r}; known: {', '.join(METHODS)}")
    if not MODELS[model].actions:
        raise SettingsError(f"{model} gives decisions no likelihood: nothing to refine")
    began = time.perf_counter()
    pool = ProcessPoolExecutor(max_workers=workers) if workers > 1 else None
    try:
        objective = Objective(traces, model, base, bounds, pool)
        start_ll, _ = objective.evidence(dict(start))
        u0 = np.array([b.to_unit(start[n]) for n, b in bounds.items()])
        options: dict[str, Any] = {"maxfev": max_evals}
        if method == "powell":
            options |= {"xtol": 1e-3, "ftol": 1e-6, "direc": np.eye(len(u0)) * 0.25}
        else:
            options |= {"xatol": 2e-3, "fatol": 0.01, "initial_simplex": _simplex(u0)}
        result = minimize(objective, u0, method=method, bounds=[(0.0, 1.0)] * len(u0), options=options)
    finally:
        if pool is not None:
            pool.shutdown()
    objective.evidence(objective.point(result.x))
    key, (ll, actions) = max(objective.cache.items(), key=lambda item: item[1][0])
    return Refinement(
        model=model,
        method=method,
        start=dict(start),
        start_log_likelihood=start_ll,
        point=dict(zip(bounds, key, strict=True)),
        log_likelihood=ll,
        actions=actions,
        evaluations=len(objective.cache),
        converged=bool(result.success),
        message=str(result.message),
        seconds=round(time.perf_counter() - began, 2),
        bounds={n: (b.low, b.high) for n, b in bounds.items()},
    )


def _simplex(u0: np.ndarray, step: float = 0.15) -> np.ndarray:
    """``(d + 1, d)`` Nelder-Mead's first simplex: ``u0`` and one step along each axis
    (inward where ``u0`` is at an upper bound)."""
    simplex = np.repeat(u0[None], len(u0) + 1, axis=0)
    for i in range(len(u0)):
        simplex[i + 1, i] += step if u0[i] + step <= 1.0 else -step
    return simplex


def refinement_lines(refined: Mapping[str, Any]) -> list[str]:
    """``report.md``'s section on ``fit.json``'s ``refinement``."""

    def values(point: Mapping[str, float]) -> str:
        return ", ".join(f"{k}={v:.4g}" for k, v in point.items())

    actions = max(int(refined["actions"]), 1)
    bounds = ", ".join(f"{k} in [{lo:g}, {hi:g}]" for k, (lo, hi) in refined["bounds"].items())
    return [
        "## Refined by the optimiser",
        "",
        f"{refined['model']}, every recording, scipy.optimize.minimize ({refined['method']}) from the "
        f"grid's best point; bounds {bounds}.",
        "",
        "| | point | log-likelihood | per action |",
        "|---|---|---|---|",
        f"| grid | {values(refined['start'])} | {refined['start_log_likelihood']:.3f} | "
        f"{refined['start_log_likelihood'] / actions:.5f} |",
        f"| optimiser | {values(refined['point'])} | {refined['log_likelihood']:.3f} | "
        f"{refined['log_likelihood'] / actions:.5f} |",
        "",
        f"{refined['evaluations']} points evaluated in {refined['seconds']:.1f} s; converged: "
        f"{'yes' if refined['converged'] else 'no'} ({refined['message']}).",
        "",
    ]
