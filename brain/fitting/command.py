"""``python -m brain fit`` (``toyroom fit`` starts it): the parser and the main."""

from __future__ import annotations

import argparse
import sys
import tempfile
from collections.abc import Sequence
from pathlib import Path

from bridge.flags import add_log_level, add_settings_args, command_parser

from ..errors import SettingsError
from ..settings import Settings
from .fit import fit, write_fit
from .grid import GRIDS, parse_grid
from .search import DEFAULT_MODELS, MODELS


def fit_parser() -> argparse.ArgumentParser:
    parser = command_parser("python -m brain fit", "Fit the model's parameters to recorded episodes.")
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
    parser.add_argument("--folds", type=int, default=5, help="k of k-fold cross-validation by episode")
    parser.add_argument("--seed", type=int, default=0, help="seed of the folds and the bootstrap")
    parser.add_argument("--workers", type=int, default=2, help="processes")
    parser.add_argument(
        "--out", type=Path, required=True, help="directory for settings.toml, fit.json, report.md"
    )
    parser.add_argument("--no-progress", action="store_true", help="no progress bar")


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


def fit_main(args: argparse.Namespace, settings: Settings, argv: Sequence[str]) -> int:
    """Run the fit and print the report."""
    grid = parse_grid(args.params, args.grid)
    models = [m.strip() for m in args.models.split(",") if m.strip()]
    with tempfile.TemporaryDirectory() as scratch:
        traces = as_traces(args.recordings, Path(scratch))
        fits = fit(traces, grid, models, settings, args.folds, args.seed, args.workers, not args.no_progress)
        summary = write_fit(args.out, fits, list(args.recordings), grid, settings, args.seed, argv)
    print((args.out / "report.md").read_text(encoding="utf-8"))
    print(f"brain: wrote {args.out / 'settings.toml'} (fitted: {summary['models'][models[0]]['fitted']})")
    sys.stdout.flush()
    return 0
