"""``toyroom eval``: measure the brain on random episodes with simulated people, under one
condition or several (:mod:`toyroom.evaluation`), with a progress bar; ``--days N``: households
over days (:mod:`toyroom.evaluation.households`). Its options, their checks, and the runs."""

from __future__ import annotations

import argparse
import shlex
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

from bridge.flags import add_settings_args, settings_argv
from bridge.processes import check_brain_settings
from protocol import MAX_DAYS, MAX_TICKS, OBSERVING, EpisodeKind, Minds, Perception, Policy, TaskKind
from toyroom.evaluation.conditions import POLICIES, Condition

from ..choicehelp import KIND_NOTES, MINDS_NOTES, PERCEPTION_NOTES, POLICY_NOTES, described
from ..subcommand import Subcommand

if TYPE_CHECKING:
    from toyroom.evaluation.summary import Evaluation

BATCH = 10
"""``toyroom eval --batch``'s default: episodes of a condition that share one process pair."""


def options(evaluation: argparse.ArgumentParser) -> None:
    """``toyroom eval``'s options."""
    evaluation.add_argument("--episodes", type=int, default=40, help="how many episodes")
    evaluation.add_argument("--seed", type=int, default=1, help="sweep seed (episode i gets 1000 x seed + i)")
    evaluation.add_argument("--workers", type=int, default=2, help="episodes at a time")
    evaluation.add_argument(
        "--backend", choices=("local", "ray"), default="local", help="local threads, or Ray tasks"
    )
    evaluation.add_argument(
        "--address",
        metavar="HOST:PORT",
        help="with --backend ray: the Ray cluster to run on (default: $RAY_ADDRESS; none: a Ray "
        "started here, on loopback); each node runs its episodes' engines and brains on its own "
        "loopback (docs/deployment.md)",
    )
    evaluation.add_argument(
        "--out", type=Path, default=Path("out/eval"), help="directory for metrics and report"
    )
    evaluation.add_argument(
        "--perception",
        default=Perception.OMNISCIENT.value,
        help=f"{described(Perception, PERCEPTION_NOTES)}; comma-separated for several conditions",
    )
    evaluation.add_argument(
        "--minds",
        default=Minds.SIMPLE.value,
        help=f"{described(Minds, MINDS_NOTES)}; comma-separated",
    )
    evaluation.add_argument(
        "--kind",
        default=EpisodeKind.EVERYDAY.value,
        help=f"{described(EpisodeKind, KIND_NOTES)}; comma-separated",
    )
    evaluation.add_argument(
        "--tasks",
        default="",
        help="with --kind tasks: the task kinds episodes are drawn from in turn, comma-separated: "
        f"{', '.join(TaskKind.names())} (default: all)",
    )
    evaluation.add_argument(
        "--autonomy",
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="set one of the simulated people's [autonomy] settings in every episode, over the drawn "
        "one (a TOML value, e.g. replan_lag=[100000,100000]: people who never turn back on their own; "
        "docs/evaluation.md); repeatable",
    )
    evaluation.add_argument(
        "--policies",
        default=Policy.TOM.value,
        help="the acting robot's policies, one run each, comma-separated: "
        f"{described(Policy, POLICY_NOTES, last=', ')}; "
        f"{OBSERVING} (observing) is always run: --policies {OBSERVING} runs it alone",
    )
    evaluation.add_argument(
        "--max-ticks", type=int, default=MAX_TICKS, help="ticks per episode (default: %(default)s)"
    )
    evaluation.add_argument(
        "--days",
        type=int,
        default=1,
        help="live each episode as a household over this many days, each starting where the last "
        "ended (overnight changes, favourites that drift: docs/evaluation.md), the brain with a "
        "memory of each person; scored per day against a brain without memory (default: 1, an "
        f"episode of its own; at most {MAX_DAYS}; resumed a chain's day at a time)",
    )
    evaluation.add_argument(
        "--batch",
        type=int,
        help="at most this many episodes of a condition share one engine and one brain process "
        "per kind of run (each run still a fresh model and episode; 1: a process pair per run; "
        f"default: {BATCH}); with --days above 1, at most this many runs of a household (its "
        "chains' days, each reading and saving its chain's memory as a brain of its own would; "
        "default: all of them)",
    )
    _outputs(evaluation)
    add_settings_args(evaluation)


def _outputs(evaluation: argparse.ArgumentParser) -> None:
    """``toyroom eval``'s options on what it keeps: recordings, an unfinished evaluation."""
    evaluation.add_argument(
        "--record",
        action="store_true",
        help="keep every run's MCAP recording in OUT/recordings/CONDITION/ (for toyroom fit and infer)",
    )
    evaluation.add_argument(
        "--fresh",
        action="store_true",
        help="first remove the evaluation in --out, finished or not (other files stay); without it, a "
        "finished one is refused, and an unfinished one (stopped by Ctrl-C, or a full disk) is resumed "
        "by the same command and refused for another command or code",
    )


def handle(args: argparse.Namespace) -> int:
    """``toyroom eval``: check the options (exit 2 naming a bad one, before anything starts),
    then run the evaluation (:func:`eval_main`), or households over days (:func:`days_main`)."""
    from toyroom.evaluation.conditions import conditions
    from toyroom.evaluation.folder import check_out
    from toyroom.evaluation.generation import check_autonomy

    brain = settings_argv(args.settings, args.overrides)
    check_brain_settings(args.settings, args.overrides)  # before any process starts
    try:
        tasks = [t.strip() for t in args.tasks.split(",") if t.strip()]
        kinds = args.kind.split(",")
        chosen = conditions(args.perception.split(","), args.minds.split(","), kinds, tasks, args.autonomy)
        check_autonomy(args.autonomy)
    except ValueError as err:
        print(f"toyroom eval: {err}", file=sys.stderr)
        return 2
    named = [p for p in args.policies.split(",") if p != OBSERVING]  # always run
    unknown = [p for p in named if p not in POLICIES]
    if unknown:
        print(f"toyroom eval: unknown policies {unknown} (known: {', '.join(POLICIES)})", file=sys.stderr)
        return 2
    policies = [Policy(p) for p in named]
    for flag, value in (
        ("--episodes", args.episodes),
        ("--workers", args.workers),
        ("--batch", BATCH if args.batch is None else args.batch),
        ("--max-ticks", args.max_ticks),
        ("--days", args.days),
    ):
        if value < 1:
            print(f"toyroom eval: {flag} must be at least 1, got {value}", file=sys.stderr)
            return 2
    if args.address and args.backend != "ray":
        print("toyroom eval: --address is a Ray cluster's: it needs --backend ray", file=sys.stderr)
        return 2
    if (refusal := days_refusal(args)) is not None:
        print(f"toyroom eval: {refusal}", file=sys.stderr)
        return 2
    command = shlex.join(["toyroom", *sys.argv[1:]])
    check_out(args.out, args.fresh)  # a finished evaluation there: refused, or (--fresh) removed
    if args.days > 1:
        return days_main(args, brain, chosen, command, policies)
    return eval_main(
        args.episodes,
        args.seed,
        args.workers,
        args.backend,
        args.out,
        brain,
        chosen,
        command,
        policies,
        args.record,
        max_ticks=args.max_ticks,
        batch=BATCH if args.batch is None else args.batch,
        address=args.address,
        fresh=args.fresh,
    )


def eval_main(
    episodes: int,
    seed: int,
    workers: int,
    backend: str,
    out: Path,
    brain_args: Sequence[str] = (),
    conditions: Sequence[Condition] = (),
    command: str = "",
    policies: Sequence[Policy] = (Policy.TOM,),
    record: bool = False,
    max_ticks: int = MAX_TICKS,
    batch: int = BATCH,
    address: str | None = None,
    fresh: bool = False,
) -> int:
    """Run the evaluation with a progress bar and print the metrics (``address``: the Ray
    cluster's, with ``backend`` ``ray``). SIGINT, SIGTERM or SIGHUP stop it within seconds,
    keeping the finished episodes for the same command to resume (``128 + signal``); 1 when
    every episode failed."""
    from rich.console import Console
    from rich.markdown import Markdown
    from rich.progress import Progress

    from toyroom.evaluation.episodes import evaluate
    from toyroom.evaluation.interrupt import EvaluationStopped, catch_signals
    from toyroom.evaluation.report import report

    chosen = tuple(conditions) or (Condition(),)
    try:
        with catch_signals(), Progress() as bar:
            total = episodes * len(chosen)
            task = bar.add_task(f"{episodes} episodes x {len(chosen)} condition(s)", total=total)
            metrics = evaluate(
                episodes,
                seed,
                out,
                conditions=chosen,
                workers=workers,
                backend=backend,
                progress=lambda n: bar.advance(task, n),
                brain_args=tuple(brain_args),
                command=command,
                policies=policies,
                record=record,
                max_ticks=max_ticks,
                batch=batch,
                address=address,
                fresh=fresh,
                notify=lambda text: bar.console.print(f"toyroom eval: {text}", markup=False, soft_wrap=True),
            )
    except EvaluationStopped as err:
        print(f"toyroom eval: {err}", file=sys.stderr, flush=True)
        return 128 + err.signum
    Console().print(Markdown(report(metrics)))
    print(f"wrote {out / 'metrics.json'} and {out / 'report.md'}")
    return failed_episodes(metrics, out)


def failed_episodes(metrics: Evaluation, out: Path) -> int:
    """Say how many episodes failed, if any (on stderr); 1 when all did (there are no
    scores), else 0 (the metrics are over the others and say how many failed)."""
    failed = sum(c.numbers.episodes_failed for c in metrics.conditions)
    total = metrics.episodes * len(metrics.conditions)
    if not failed:
        return 0
    where = f"their errors are in {out / 'episodes.json'}, their nodes' logs under {out}"
    if failed == total:
        print(
            f"toyroom eval: every episode failed ({failed} of {total}), nothing scored ({where})",
            file=sys.stderr,
        )
        return 1
    print(
        f"toyroom eval: {failed} of {total} episodes failed; the metrics are over the other "
        f"{total - failed} ({where})",
        file=sys.stderr,
    )
    return 0


def days_main(
    args: argparse.Namespace,
    brain: Sequence[str],
    conditions: Sequence[Condition],
    command: str,
    policies: Sequence[Policy],
) -> int:
    """``toyroom eval --days N``: households over days (:mod:`toyroom.evaluation.households`),
    with a progress bar counting household days (``4/18 household days``); its report printed.
    ``--batch K``: at most K runs of a household (its chains' days) share one engine and one
    brain (default: all of them; 1: a process pair a run; :mod:`toyroom.evaluation.dayserver`).
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
                batch=args.batch,
                notify=lambda text: bar.console.print(f"toyroom eval: {text}", markup=False, soft_wrap=True),
            )
    except EvaluationStopped as err:
        print(f"toyroom eval: {err}", file=sys.stderr, flush=True)
        return 128 + err.signum
    Console().print(Markdown(days_report(metrics, args.out)))
    print(f"wrote {args.out / 'metrics.json'} and {args.out / 'report.md'}")
    failed = sum(bool(day.episodes_failed) for c in metrics.conditions for day in c.by_day.values())
    return 1 if failed == args.days * len(chosen) else 0


def days_refusal(args: argparse.Namespace) -> str | None:
    """Why ``--days`` cannot run with the other options given (``None``: it can)."""
    if args.days > MAX_DAYS:
        return f"--days is a household's days, 1 to {MAX_DAYS}, got {args.days}"
    return None


COMMAND = Subcommand(
    "eval", "measure the brain on random episodes with simulated people", options, handle, out_folder=True
)
