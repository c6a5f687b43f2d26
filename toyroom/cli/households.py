"""``toyroom eval --days N``: households over days (:mod:`toyroom.evaluation.households`)."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

from toyroom.evaluation.conditions import Condition


def days_main(
    args: argparse.Namespace,
    brain: Sequence[str],
    conditions: Sequence[Condition],
    command: str,
    policies: Sequence[str],
) -> int:
    """``toyroom eval --days N``: households over days (:mod:`toyroom.evaluation.households`),
    with a progress bar; its report printed. SIGINT, SIGTERM or SIGHUP stop it (``128 + signal``)."""
    from rich.console import Console
    from rich.markdown import Markdown
    from rich.progress import Progress

    from toyroom.evaluation.households import days_report, evaluate_households
    from toyroom.evaluation.interrupt import EvaluationStopped, catch_signals

    chosen = tuple(conditions) or (Condition(),)
    try:
        with catch_signals(), Progress() as bar:
            total = args.episodes * len(chosen)
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
