"""``python -m toyroom.fitting`` (``toyroom fit`` starts it): the parser and the main."""

from __future__ import annotations

import argparse
import sys
import tempfile
from collections.abc import Mapping, Sequence
from pathlib import Path

from brain.errors import BrainError, SettingsError
from brain.settings import Settings
from bridge.flags import add_log_level, add_settings_args, command_parser, out_folder_problem, two_or_more
from bridge.recording.readable import RecordingError, read_recording
from bridge.recording.trace import TraceError, read_trace
from toyroom.play.recording import complete_only

from .correlation import JudgedFit, against_first, fit_judgments, judged_search
from .crossval import folds
from .fit import ModelFit, fit, write_fit
from .grid import GRIDS, parse_grid
from .judgments import Judgment, load_judgments, rating_counts
from .optimise import BOUNDS, METHODS, Refinement, parse_bounds, refine
from .search import DEFAULT_MODELS, MODELS, model_grid


def fit_parser() -> argparse.ArgumentParser:
    """The parser of ``toyroom fit``."""
    parser = command_parser("toyroom fit", "Fit the model's parameters to recorded episodes.")
    add_fit_args(parser)
    add_settings_args(parser)
    add_log_level(parser, "WARNING")
    return parser


def add_fit_args(parser: argparse.ArgumentParser) -> None:
    """The options of ``fit`` (shared with ``toyroom fit``)."""
    parser.add_argument(
        "recordings", nargs="+", type=Path, help="trace.jsonl or .mcap files of recorded runs"
    )
    parser.add_argument(
        "--params", default="beta,hazard", help=f"parameters to fit, comma-separated (of {', '.join(GRIDS)})"
    )
    parser.add_argument(
        "--grid", action="append", default=[], metavar="NAME=V1,V2,...", help="replace one parameter's grid"
    )
    parser.add_argument(
        "--models",
        default=",".join(DEFAULT_MODELS),
        help=f"models to fit and compare, the first written as settings.toml (of {', '.join(MODELS)})",
    )
    parser.add_argument(
        "--folds",
        type=two_or_more,
        default=None,
        help=f"k of k-fold cross-validation by episode (default: {FOLDS}, or one per recording when "
        "there are fewer)",
    )
    parser.add_argument(
        "--include-incomplete",
        action="store_true",
        help="also fit toyroom play recordings marked incomplete (left out by default, and listed)",
    )
    parser.add_argument("--seed", type=int, default=0, help="seed of the folds and the bootstrap")
    parser.add_argument("--workers", type=int, default=2, help="processes (or Ray CPUs)")
    parser.add_argument(
        "--backend",
        choices=("local", "ray"),
        default="local",
        help="worker processes, or Ray tasks (the 'ray' extra)",
    )
    parser.add_argument(
        "--address",
        metavar="HOST:PORT",
        help="with --backend ray: the Ray cluster to run the grid search on (default: $RAY_ADDRESS; "
        "none: a Ray started here, on loopback); the recordings go to its nodes by value",
    )
    parser.add_argument(
        "--out", type=Path, required=True, help="directory for settings.toml, fit.json, report.md"
    )
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")
    parser.add_argument(
        "--judgments",
        type=Path,
        metavar="FILE.csv",
        help="ratings of the recordings (episode, tick, person, quantity, target, value[, estimate]; "
        "quantity belief, desire, utility, rank or false_belief; estimate online or smoothed): also fit "
        "the parameters that correlate best with them, and write those as settings.toml",
    )
    add_refine_args(parser)


def add_refine_args(parser: argparse.ArgumentParser) -> None:
    """``--refine`` and its options (:mod:`toyroom.fitting.optimise`)."""
    parser.add_argument(
        "--refine",
        action="store_true",
        help="then refine the first model's parameters on every recording with a bounded optimiser "
        "(scipy.optimize), started from the grid's best point; settings.toml gets the refined point",
    )
    parser.add_argument("--refine-method", choices=METHODS, default="powell", help="the optimiser")
    parser.add_argument(
        "--refine-evals",
        type=int,
        default=200,
        help="at most this many points (one pass over every recording each)",
    )
    parser.add_argument(
        "--bounds",
        action="append",
        default=[],
        metavar="NAME=LO,HI",
        help="replace one parameter's search range ("
        + ", ".join(f"{k} [{b.low:g}, {b.high:g}]" for k, b in BOUNDS.items())
        + "; log scale but for ignorance and step_cost)",
    )


def as_traces(paths: Sequence[Path], scratch: Path) -> list[Path]:
    """The recordings as trace files: an MCAP file converted into ``scratch``.

    Raises:
        SettingsError: naming a recording that does not exist."""
    out = []
    for i, path in enumerate(paths):
        if not path.is_file():
            raise SettingsError(f"{path}: no such recording")
        if path.suffix == ".mcap":
            from bridge.recording.mcap import mcap_to_trace

            target = scratch / f"{i:04d}-{path.stem}.jsonl"
            mcap_to_trace(path, target)
            path = target
        out.append(path)
    return out


def not_whole(paths: Sequence[Path]) -> list[str]:
    """For each recording that was cut off or damaged, a note saying what the fit stood on
    (``fit``'s report carries them, so a fit to partial recordings never looks whole)."""
    notes = []
    for path in paths:
        try:
            cut = read_recording(path).cut
        except RecordingError:
            continue  # refused already, naming the file, when it was read for the fit
        if cut is not None:
            notes.append(cut.note())
    return notes


def _judgments(path: Path, traces: Sequence[Path], recordings: Sequence[Path]) -> list[Judgment]:
    """``--judgments`` read and checked against the recordings before any fitting.

    Raises:
        SettingsError: naming a recording that cannot be read."""
    try:
        loaded = [read_trace(t) for t in traces]
    except TraceError as err:
        raise SettingsError(str(err)) from None
    return load_judgments(path, loaded, [p.stem for p in recordings])


def _judged(
    args: argparse.Namespace,
    traces: Sequence[Path],
    judgments: Sequence[Judgment],
    grid: Mapping[str, Sequence[float]],
    models: Sequence[str],
    settings: Settings,
) -> list[JudgedFit]:
    """Every model fitted to ``--judgments`` (the same folds as the likelihood fit)."""
    found = judged_search(traces, models, grid, settings.model, judgments, args.workers, not args.no_progress)
    parts = folds(len(traces), args.folds, args.seed)
    fitted = [fit_judgments(m, *found[m], judgments, parts, args.seed) for m in models]
    return against_first(fitted, judgments, args.seed)


def _refined(
    args: argparse.Namespace,
    traces: Sequence[Path],
    fits: Sequence[ModelFit],
    grid: Mapping[str, Sequence[float]],
    settings: Settings,
) -> Refinement | None:
    """``--refine``: the first model refined from its grid point (``None`` without it)."""
    if not args.refine:
        return None
    first = fits[0]
    bounds = parse_bounds(list(model_grid(first.table.model, grid)), args.bounds)
    if not bounds:
        raise SettingsError(f"--refine: {first.table.model} has no parameter of --params to refine")
    return refine(
        traces,
        first.table.model,
        first.fitted,
        settings.model,
        bounds,
        args.refine_method,
        args.refine_evals,
        args.workers,
    )


FOLDS = 5
"""``--folds``' default, when there are that many recordings."""


def fold_count(asked: int | None, recordings: int) -> int:
    """The folds of the cross-validation: ``asked``, or :data:`FOLDS` or one per recording when
    there are fewer (said on stdout).

    Raises:
        SettingsError: fewer than two recordings, or fewer than the folds asked for."""
    if recordings < 2:
        raise SettingsError(f"cross-validation needs at least 2 recordings, got {recordings}")
    if asked is None and recordings < FOLDS:
        print(f"toyroom fit: {recordings} recordings, so {recordings}-fold cross-validation (not {FOLDS})")
    k = asked if asked is not None else min(FOLDS, recordings)
    if recordings < k:
        raise SettingsError(f"{k}-fold cross-validation needs at least {k} recordings, got {recordings}")
    return k


def fit_main(args: argparse.Namespace, settings: Settings, argv: Sequence[str]) -> int:
    """Run the fit and print the report."""
    if args.address and args.backend != "ray":
        raise SettingsError("--address is a Ray cluster's: it needs --backend ray")
    if (problem := out_folder_problem(args.out)) is not None:  # before minutes of fitting
        raise BrainError(problem)
    grid = parse_grid(args.params, args.grid)
    models = [m.strip() for m in args.models.split(",") if m.strip()]
    if args.refine:
        parse_bounds(list(model_grid(models[0], grid)) if models[0] in MODELS else [], args.bounds)
    args.recordings, left = complete_only(args.recordings, args.include_incomplete)
    for note in left:
        print(f"toyroom fit: excluded an incomplete play recording: {note} (--include-incomplete keeps it)")
    with tempfile.TemporaryDirectory() as scratch:
        traces = as_traces(args.recordings, Path(scratch))
        args.folds = fold_count(args.folds, len(traces))
        judgments = _judgments(args.judgments, traces, args.recordings) if args.judgments else []
        fits = fit(
            traces,
            grid,
            models,
            settings,
            args.folds,
            args.seed,
            args.workers,
            not args.no_progress,
            args.backend,
            args.address,
        )
        judged = _judged(args, traces, judgments, grid, models, settings) if judgments else []
        refined = _refined(args, traces, fits, grid, settings)
        summary = write_fit(
            args.out,
            fits,
            list(args.recordings),
            grid,
            settings,
            args.seed,
            argv,
            judged,
            refined,
            not_whole(args.recordings),
            rating_counts(args.judgments) if args.judgments else None,
        )
    print((args.out / "report.md").read_text(encoding="utf-8"))
    for file, w in summary["written"].items():
        print(f"toyroom fit: wrote {args.out / file} ({w['model']} fitted by {w['by']}: {w['point']})")
    sys.stdout.flush()
    return 0
