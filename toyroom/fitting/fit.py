"""``toyroom fit``: parameters by maximum marginal likelihood over recorded episodes,
cross-validated by episode, and the models compared by held-out log-likelihood per action.

Writes into the output folder: ``settings.toml`` (the first model fitted on every
recording: the optimiser's point when ``--refine`` ran, :mod:`toyroom.fitting.optimise`),
``fit.json`` (grids, every fold, every model's held-out score with a bootstrap 95% interval,
paired against the best, and the optimiser's result under ``refinement``), ``folds.csv`` and
``report.md``.
"""

from __future__ import annotations

import csv
import io
import json
import math
import shlex
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from brain.errors import SettingsError
from brain.settings import Settings, settings_toml
from bridge.recording.atomic import write_texts
from bridge.recording.trace import TraceError, read_trace
from toyroom.evaluation.intervals import pooled_means

from .correlation import JudgedFit
from .crossval import Fold, best_point, cross_validate, folds, held_out_per_action
from .optimise import Refinement, refinement_lines
from .search import BRAIN_MODELS, MODELS, Table, model_settings, search


@dataclass(frozen=True)
class ModelFit:
    """One model's cross-validated fit."""

    table: Table
    folds: list[Fold]
    fitted: dict[str, float]
    """The point fitted on every recording."""

    @property
    def held_out(self) -> float:
        return held_out_per_action(self.folds)

    def per_episode(self) -> list[tuple[float, int]]:
        """Each episode's held-out ``(log-likelihood, actions)`` (at its fold's point)."""
        out: list[tuple[float, int]] = [(0.0, 0)] * self.table.ll.shape[1]
        for fold in self.folds:
            for e in fold.held_out:
                out[e] = (float(self.table.ll[fold.best, e]), int(self.table.actions[e]))
        return out


def check_recordings(paths: Sequence[Path], k: int) -> None:
    """Every recording readable, and enough of them for ``k`` folds.

    Raises:
        SettingsError: naming the recording that cannot be read and why, or the count."""
    for path in paths:
        try:
            read_trace(path)
        except TraceError as err:
            raise SettingsError(str(err)) from None
    if len(paths) < k:
        raise SettingsError(f"{k}-fold cross-validation needs at least {k} recordings, got {len(paths)}")


def check_models(models: Sequence[str]) -> None:
    """Every model known, and the first one the brain's.

    Raises:
        SettingsError: naming what is wrong."""
    unknown = [m for m in models if m not in MODELS]
    if unknown or not models:
        raise SettingsError(f"unknown models {unknown}; known: {', '.join(MODELS)}")
    if models[0] not in BRAIN_MODELS:
        raise SettingsError(
            f"the first model's fit is written as settings.toml, so it must be one of the brain's "
            f"({', '.join(BRAIN_MODELS)}), got {models[0]!r}"
        )


def fit(
    traces: Sequence[Path],
    grid: Mapping[str, Sequence[float]],
    models: Sequence[str],
    settings: Settings,
    k: int = 5,
    seed: int = 0,
    workers: int = 2,
    progress: bool = True,
    backend: str = "local",
    address: str | None = None,
) -> list[ModelFit]:
    """Search, then cross-validate each model with a model of actions (folds shared by every
    model); ``backend`` and ``address``: where the search runs (:func:`~.search.search`).

    Raises:
        SettingsError: naming an unknown model, or a first model that is not the brain's
            (its fit is written as ``settings.toml``)."""
    check_models(models)
    check_recordings(traces, k)
    acting = [m for m in models if MODELS[m].actions]
    tables = search(traces, acting, grid, settings.model, workers, progress, backend, address)
    parts = folds(len(traces), k, seed)
    return [ModelFit(t, cross_validate(t.ll, t.actions, parts), t.points[best_point(t.ll)]) for t in tables]


def write_fit(
    out: Path,
    fits: list[ModelFit],
    traces: Sequence[Path],
    grid: Mapping[str, Sequence[float]],
    settings: Settings,
    seed: int,
    command: Sequence[str],
    judged: Sequence[JudgedFit] = (),
    refined: Refinement | None = None,
    notes: Sequence[str] = (),
    ratings: Mapping[str, int] | None = None,
) -> dict[str, Any]:
    """The outputs (see the module docstring); returns ``fit.json``'s content. With
    ``judged`` (a fit to judgments), ``settings.toml`` holds its first model's point; else,
    with ``refined`` (the optimiser's result), its point; ``settings-likelihood.toml`` always
    holds the likelihood fit's (refined) point, and the report says which point each file has.
    ``notes`` say which recordings were not whole (cut off or damaged) and what of them was
    used; ``ratings`` counts the judgments file's ratings, raters and rated recordings."""
    out.mkdir(parents=True, exist_ok=True)
    first = fits[0]
    likely = (refined.model, refined.point) if refined is not None else (first.table.model, first.fitted)
    name, point = (judged[0].model, judged[0].fitted) if judged else likely
    files: dict[str, str] = {}  # written together at the end, all whole or none
    for file, (model, at) in (("settings.toml", (name, point)), ("settings-likelihood.toml", likely)):
        fitted = Settings(model=model_settings(model, settings.model, at), robot=settings.robot)
        files[file] = settings_toml(fitted)
    ranked = sorted(fits, key=lambda f: -f.held_out)
    intervals, differences = pooled_means({f.table.model: f.per_episode() for f in ranked}, seed)
    summary = {
        "command": shlex.join(command),
        "recordings": [str(p) for p in traces],
        "grid": {k: list(v) for k, v in grid.items()},
        "models": {
            f.table.model: {
                "fitted": f.fitted,
                "held_out_per_action": intervals[f.table.model],
                "minus_best": _negated(differences.get(f.table.model)),
                "folds": [
                    {
                        "held_out": list(d.held_out),
                        "point": f.table.points[d.best],
                        "log_likelihood": d.log_likelihood,
                        "actions": d.actions,
                        "per_action": d.per_action,
                    }
                    for d in f.folds
                ],
            }
            for f in fits
        },
        "ranking": [f.table.model for f in ranked],
        "recordings_not_whole": list(notes),
        "written": {
            "settings.toml": {"model": name, "point": point, "by": "judgments" if judged else "likelihood"},
            "settings-likelihood.toml": {"model": likely[0], "point": likely[1], "by": "likelihood"},
        },
    }
    if ratings is not None:
        summary["ratings"] = dict(ratings)
    if refined is not None:
        summary["refinement"] = refined.as_json()
    if judged:
        summary["judgments"] = {
            j.model: {
                "fitted": j.fitted,
                "r": j.r,
                "minus_first": j.minus_first,
                "fold_points": [j.points[p] for p in j.fold_points],
            }
            for j in judged
        }
    files |= {"fit.json": json.dumps(summary, indent=2), "folds.csv": _folds_csv(fits, traces)}
    write_texts(out, files | {"report.md": report(summary)})
    return summary


def _folds_csv(fits: list[ModelFit], traces: Sequence[Path]) -> str:
    """``folds.csv``: each model's folds, their held-out recordings and points."""
    with io.StringIO(newline="") as handle:
        writer = csv.writer(handle)
        writer.writerow(["model", "fold", "held_out", "point", "log_likelihood", "actions", "per_action"])
        for f in fits:
            for i, d in enumerate(f.folds):
                names = ";".join(str(traces[e]) for e in d.held_out)
                point = ";".join(f"{k}={v:g}" for k, v in f.table.points[d.best].items())
                writer.writerow(
                    [
                        f.table.model,
                        i,
                        names,
                        point,
                        f"{d.log_likelihood:.4f}",
                        d.actions,
                        f"{d.per_action:.5f}",
                    ]
                )
        return handle.getvalue()


def report(summary: Mapping[str, Any]) -> str:
    """``report.md``: the command, the grid and the model comparison."""
    best = summary["ranking"][0]
    lines = [
        "# Fit",
        "",
        f"`{summary['command']}`",
        "",
        f"{len(summary['recordings'])} recordings; grid: "
        + ", ".join(f"{k} in {{{', '.join(f'{v:g}' for v in vs)}}}" for k, vs in summary["grid"].items()),
        "",
        *[f"{note.strip()}\n" for note in summary.get("recordings_not_whole", ())],
        "Held-out log-likelihood per action (natural log; higher is better), each episode scored at",
        "the point fitted without its fold; bootstrap 95% intervals over episodes; differences paired",
        "by episode.",
        "",
        f"| model | held-out log-lik. per action | minus {best} | fitted on all recordings |",
        "|---|---|---|---|",
    ]
    for name in summary["ranking"]:
        m = summary["models"][name]
        diff = m["minus_best"]
        lines.append(
            f"| {name} | {_interval(m['held_out_per_action'])} | "
            f"{_interval(diff) if diff else '-'} | "
            + ", ".join(f"{k}={v:g}" for k, v in m["fitted"].items())
            + " |"
        )
    lines += [
        "",
        f"Without a model of actions ({', '.join(m for m, spec in MODELS.items() if not spec.actions)}), "
        "an observer gives decisions no likelihood: it is compared on judgments only.",
        "",
    ]
    if "refinement" in summary:
        lines += refinement_lines(summary["refinement"])
    if "judgments" in summary:
        lines += _judgments_table(summary["judgments"], summary.get("ratings"))
    lines += _written_lines(summary["written"])
    return "\n".join(lines)


def _written_lines(written: Mapping[str, Any]) -> list[str]:
    """Which point each settings file holds, and from which fit."""
    how = {
        "judgments": "the fit to judgments (best mean r over kinds of judgment, all recordings)",
        "likelihood": "the likelihood fit (best log-likelihood of the actions, all recordings)",
    }
    lines = ["## Written", ""]
    for file, w in written.items():
        point = ", ".join(f"{k}={v:g}" for k, v in w["point"].items()) or "(no parameters)"
        lines.append(f"- `{file}`: {w['model']} at {point}, from {how[w['by']]}.")
    same = len({tuple(sorted(w["point"].items())) for w in written.values()}) == 1
    if not same:
        lines.append(
            "- The two fits chose different points: they answer different questions (what people "
            "do, what raters judge); `--set`/`--settings` runs either."
        )
    return [*lines, ""]


def _judgments_table(judged: Mapping[str, Any], ratings: Mapping[str, int] | None = None) -> list[str]:
    quantities = sorted({q for m in judged.values() for q in m["r"]})
    counted = []
    if ratings:
        named = ratings["raters"]
        raters = f"{named} raters" if named else "raters not named (no participant column)"
        counted = [
            f"{ratings['ratings']} ratings by {raters}, of {ratings['episodes']} recording(s); "
            "ratings of one question are averaged over raters.",
            "",
        ]
    lines = [
        "## Fit to judgments",
        "",
        *counted,
        "Correlation between each model's estimates (online, or smoothed where the rating says so)",
        "and the ratings (Pearson's r; Spearman's for ranks), each episode predicted at the point",
        "fitted (best mean r over kinds of judgment) without its fold; bootstrap 95% intervals over",
        "episodes; after each, minus the first model's r, paired by episode. The motion heuristic's",
        "beliefs are the truth, it has no false beliefs and answers smoothed questions online.",
        "",
        "| model | " + " | ".join(f"r {q}" for q in quantities) + " | fitted on all |",
        "|---|" + "---|" * len(quantities) + "---|",
    ]
    first = next(iter(judged), "")
    for name, m in judged.items():
        minus = m.get("minus_first") or {}
        cells = [
            _interval(m["r"].get(q, {})) + (f"; minus {first} {_interval(minus[q])}" if q in minus else "")
            for q in quantities
        ]
        point = ", ".join(f"{k}={v:g}" for k, v in m["fitted"].items()) or "(no parameters)"
        lines.append(f"| {name} | " + " | ".join(cells) + f" | {point} |")
    return [*lines, "", *_judged_notes(judged, quantities)]


FEW = 5
"""Kinds of judgment rated on fewer recordings than this get a note: their interval says little."""


def _judged_notes(judged: Mapping[str, Any], quantities: Sequence[str]) -> list[str]:
    """Why a cell has no r (``-``), and which kinds rest on one rated recording (their interval
    over recordings is no interval, and every model fitted on it picks its point on the same
    ratings)."""
    notes = []
    for name, m in judged.items():
        for q in quantities:
            why = m["r"].get(q, {}).get("why")
            if why:
                notes.append(f"- {name}, {q}: no r ({why}).")
    rated = {q: min(m["r"].get(q, {}).get("episodes", FEW) for m in judged.values()) for q in quantities}
    single = [q for q, n in rated.items() if n == 1]
    few = [f"{q} ({n})" for q, n in rated.items() if 1 < n < FEW]
    if single:
        notes.append(
            f"- {', '.join(single)}: rated on one recording only, so the bootstrap over recordings has "
            "nothing to resample (no interval) and the cross-validation cannot hold that recording "
            "out and still fit; rate more recordings for an interval."
        )
    if few:
        notes.append(
            f"- {', '.join(few)}: rated on fewer than {FEW} recordings: a resample of so few recordings "
            "often has too few rated values for an r, so the interval barely moves from the mean and "
            "says little; rate more recordings."
        )
    return [*notes, ""] if notes else []


def _negated(d: Mapping[str, float | None] | None) -> dict[str, float | None] | None:
    """``best - model`` as ``model - best``."""
    if d is None:
        return None
    flip = {"mean": "mean", "lo": "hi", "hi": "lo"}
    return {k: (-v if (v := d[flip[k]]) is not None else None) for k in ("mean", "lo", "hi")}


def _interval(value: Mapping[str, Any]) -> str:
    mean, lo, hi = value.get("mean"), value.get("lo"), value.get("hi")
    if mean is None or not math.isfinite(mean):
        return "-"
    if lo is not None and hi is not None and not (math.isfinite(lo) and math.isfinite(hi)):
        return f"{mean:.4f}"
    return f"{mean:.4f}" if lo is None else f"{mean:.4f} [{lo:.4f}, {hi:.4f}]"
