"""``toyroom eval --days N``: households over days (:mod:`toyroom.evaluation.households`)."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from protocol import MAX_DAYS, Policy
from toyroom.evaluation.conditions import Condition


def days_main(
    args: argparse.Namespace,
    brain: Sequence[str],
    conditions: Sequence[Condition],
    command: str,
    policies: Sequence[Policy],
) -> int:
    """``toyroom eval --days N``: households over days (:mod:`toyroom.evaluation.households`),
    with a progress bar counting household days (``4/18 household days``); its report printed.
    SIGINT, SIGTERM or SIGHUP stop it (``128 + signal``), keeping the finished days for the same
    command to resume (:mod:`toyroom.evaluation.chaindays`)."""
    from rich.console import Console
    from rich.markdown import Markdown
    from rich.progress import BarColumn, MofNCompleteColumn, Progress, TextColumn, TimeRemainingColumn

    from toyroom.evaluation.days import days_report
    from toyroom.evaluation.households import evaluate_households
    from toyroom.evaluation.interrupt import EvaluationStopped, catch_signals

    chosen = tuple(conditions) or (Condition(),)
    try:
        columns = (TextColumn("{task.description}"), BarColumn(), MofNCompleteColumn())
        unit = (TextColumn("household days"), TimeRemainingColumn())
        with catch_signals(), Progress(*columns, *unit) as bar:
            total = args.episodes * len(chosen) * args.days
            task = bar.add_task(f"{args.episodes} households x {args.days} days", total=total)
            metrics = evaluate_households(
                args.episodes,
                args.seed,
                args.out,
                args.days,
                conditions=chosen,
                workers=args.workers,
                brain_args=tuple(brain),
                command=command,
                policies=policies,
                record=args.record,
                max_ticks=args.max_ticks,
                progress=lambda n: bar.advance(task, n),
                fresh=args.fresh,
                backend=args.backend,
                address=args.address,
                notify=lambda text: bar.console.print(f"toyroom eval: {text}", markup=False, soft_wrap=True),
            )
    except EvaluationStopped as err:
        print(f"toyroom eval: {err}", file=sys.stderr, flush=True)
        return 128 + err.signum
    Console().print(Markdown(days_report(metrics, args.out)))
    print(f"wrote {args.out / 'metrics.json'} and {args.out / 'report.md'}")
    failed = sum(
        bool(day.get("episodes_failed")) for c in metrics["conditions"] for day in c["by_day"].values()
    )
    return 1 if failed == args.days * len(chosen) else 0


def days_refusal(args: argparse.Namespace) -> str | None:
    """Why ``--days`` cannot run with the other options given (``None``: it can)."""
    if args.days > MAX_DAYS:
        return f"--days is a household's days, 1 to {MAX_DAYS}, got {args.days}"
    if args.days > 1 and args.batch is not None:
        return (
            f"--batch is not used with --days {args.days} (each day of a household is its own "
            "engine and brain): leave it out"
        )
    return None
