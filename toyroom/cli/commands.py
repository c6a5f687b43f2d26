"""What each ``toyroom`` command does with its parsed arguments (:data:`COMMANDS`), and the
commands that run a node package as its own process (:data:`NODES`, :func:`exec_node`).
Nodes are started as processes; this module never imports ``sim2d`` or ``brain``."""

from __future__ import annotations

import argparse
import logging
import os
import shlex
import sys
import threading
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from bridge.flags import PROG_ENV, settings_argv
from bridge.processes import check_brain_settings, node_environment, stop_on_signals, wait_for_stop
from bridge.session import SessionSettings, settings_from_args
from protocol import MAX_TICKS, OBSERVING, Observer, Policy, RobotMode
from toyroom.evaluation.conditions import POLICIES, Condition

from .households import days_refusal

log = logging.getLogger("toyroom.bridge")

BATCH = 10
"""``toyroom eval --batch``'s default: episodes of a condition that share one process pair."""

CSHARP_MESSAGES = "clients/unity/Runtime/Protocol/Messages.g.cs"
"""The C# SDK's generated message classes, in the source checkout."""


def csharp_main(check: bool) -> int:
    """Write the C# message classes from the schemas, or with ``check`` return 1 when stale."""
    from bridge.processes import CHECKOUT
    from protocol.csharp import render_from_schemas

    path = CHECKOUT / CSHARP_MESSAGES
    if not (CHECKOUT / "clients" / "unity").is_dir():
        print(f"toyroom schema --csharp needs a source checkout ({CSHARP_MESSAGES})", file=sys.stderr)
        return 2
    text = render_from_schemas()
    if check:
        if not path.exists() or path.read_text(encoding="utf-8") != text:
            print(f"stale C# classes {path}: run `toyroom schema --csharp`", file=sys.stderr)
            return 1
        print(f"C# classes in {path} are up to date")
        return 0
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text, encoding="utf-8")
    print(f"wrote {path}")
    return 0


def schema_main(check: bool, directory: Path | None = None, csharp: bool = False) -> int:
    """Write the JSON Schemas, or with ``check`` report stale ones and return 1; with
    ``csharp``, the C# SDK's message classes instead."""
    from protocol.schema import SCHEMA_DIR, stale_schemas, write_schemas

    if csharp:
        return csharp_main(check)

    target = directory or SCHEMA_DIR
    if check:
        problems = stale_schemas(target)
        for line in problems:
            print(f"stale schema {target / line}", file=sys.stderr)
        if problems:
            print("run `toyroom schema` to regenerate them", file=sys.stderr)
            return 1
        print(f"schemas in {target} are up to date")
        return 0
    for path in write_schemas(target):
        print(f"wrote {path}")
    return 0


def router_main(listen: Sequence[str], config_file: Path | None) -> int:
    """Run a Zenoh router until interrupted (a warning when it listens beyond loopback:
    secure such a setup with TLS and access control, ``docs/deployment.md``)."""
    from bridge.session import Router

    stop = threading.Event()
    stop_on_signals(stop)
    with Router(listen, config_file=config_file) as router:
        log.info("router %s listening on %s", router.session.zid(), ", ".join(router.listen))
        print(f"toyroom router listening on {', '.join(router.listen)}", flush=True)
        wait_for_stop(stop)
    return 0


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


def failed_episodes(metrics: dict[str, Any], out: Path) -> int:
    """Say how many episodes failed, if any (on stderr); 1 when all did (there are no
    scores), else 0 (the metrics are over the others and say how many failed)."""
    failed = sum(c["episodes_failed"] for c in metrics["conditions"])
    total = metrics["episodes"] * len(metrics["conditions"])
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


def record_main(world: str, settings: SessionSettings, path: Path) -> int:
    """Record every message of ``world`` to ``path`` until SIGINT or SIGTERM."""
    from bridge.bridge import Bridge
    from bridge.recording.mcap import McapRecorder

    stop = threading.Event()
    stop_on_signals(stop)
    with Bridge(world, settings) as bridge, McapRecorder(bridge, path) as recorder:
        print(f"toyroom record: world '{world}' to {path}", flush=True)
        wait_for_stop(stop)
        count = recorder.count
    if recorder.error is not None:  # a full disk: what came after the failure is lost
        print(f"toyroom record: {recorder.error}; kept the first {count} messages in {path}", file=sys.stderr)
        return 1
    print(f"toyroom record: {count} messages in {path}")
    return 0


def conform_main(world: str, settings: SessionSettings, timeout: float, strict: bool = False) -> int:
    """Run the conformance kit against the engine of ``world``; 1 when a check fails (or,
    with ``strict``, is skipped)."""
    from bridge.bridge import Bridge
    from bridge.conformance.checks import check_engine, summary
    from bridge.conformance.probe import CheckOutcome

    with Bridge(world, settings) as bridge:
        results = check_engine(bridge, timeout)
    for result in results:
        print(result.line())
    print(summary(results))
    skipped = any(r.outcome is CheckOutcome.SKIPPED for r in results)
    if strict and skipped:
        print("conform --strict: a skipped check counts as failed (run a scene where each can run)")
    return 1 if any(r.failed for r in results) or (strict and skipped) else 0


def doctor_main(world: str, settings: SessionSettings) -> int:
    """Check the installation end to end; see :mod:`toyroom.cli.doctor`."""
    from .doctor import run_doctor

    return run_doctor(world, settings)


NODES = {
    "sim": ("sim2d", ()),
    "brain": ("brain", ()),
    "view": ("toyroom.view", ()),
    "gateway": ("toyroom.gateway", ()),
    "play": ("toyroom.play", ()),
    "generate": ("sim2d", ("generate",)),
    "export-scenario": ("sim2d", ("export",)),
    "fit": ("toyroom.fitting", ()),
    "rate": ("toyroom.rating", ()),
    "memory": ("brain", ("memory",)),
    "morning": ("toyroom.cli.morning", ()),
}
"""Commands that run a node package as its own process (``toyroom sim`` -> ``python -m
sim2d``, ``toyroom generate`` -> ``python -m sim2d generate``), with their options."""


def exec_node(command: str, argv: Sequence[str], prog: str | None = None) -> int:
    """Replace this process with the node of ``command`` (signals go straight to it); its
    help and errors name ``prog`` (default: ``toyroom COMMAND``)."""
    package, leading = NODES[command]
    env = node_environment(child=False)  # single-threaded BLAS: fit's worker processes use every core
    env[PROG_ENV] = prog or f"toyroom {command}"
    os.execve(sys.executable, [sys.executable, "-m", package, *leading, *argv], env)
    return 0  # pragma: no cover - execv does not return


def _schema(args: argparse.Namespace) -> int:
    return schema_main(args.check, args.dir, args.csharp)


def _router(args: argparse.Namespace) -> int:
    from bridge.session import DEFAULT_ROUTER_ENDPOINT

    default = [] if args.zenoh_config else [DEFAULT_ROUTER_ENDPOINT]  # a config file says where
    return router_main(args.listen or default, args.zenoh_config)


def _doctor(args: argparse.Namespace) -> int:
    return doctor_main(args.world, settings_from_args(args))


def _run(args: argparse.Namespace) -> int:
    from .run import RunConfig, run

    config = RunConfig(
        scenario=args.scenario,
        out=args.out,
        seed=args.seed,
        observer=Observer(args.observer),
        world=args.world if args.world != "default" else None,
        timeout=args.timeout,
        log_level=args.log_level or "WARNING",
        robot=RobotMode(args.robot) if args.robot else None,
        engine=args.engine,
        gateway=args.gateway,
        live=False if args.no_live else None,
        record=args.record,
        view=args.view,
        shadows=tuple(args.shadow),
        settings=args.settings,
        overrides=tuple(args.overrides),
        memory=args.memory,
        **({"lease_ms": args.lease_ms} if args.lease_ms is not None else {}),
    )
    return run(config, settings_from_args(args))


def _bench(args: argparse.Namespace) -> int:
    flags = (["--quick"] if args.quick else []) + (["--memory"] if args.memory else [])
    os.execv(sys.executable, [sys.executable, "-m", "toyroom.bench", *flags, "--out", str(args.out)])
    return 0  # pragma: no cover - execv does not return


def _eval(args: argparse.Namespace) -> int:
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
        from .households import days_main

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


def _conform(args: argparse.Namespace) -> int:
    return conform_main(args.world, settings_from_args(args), args.timeout, args.strict)


def _infer(args: argparse.Namespace) -> int:
    from .recordings import infer_main

    return infer_main(args)


def _replay(args: argparse.Namespace) -> int:
    from .recordings import replay_main

    return replay_main(args)


def _record(args: argparse.Namespace) -> int:
    return record_main(args.world, settings_from_args(args), args.file)


COMMANDS = {
    "schema": _schema,
    "router": _router,
    "doctor": _doctor,
    "run": _run,
    "bench": _bench,
    "eval": _eval,
    "conform": _conform,
    "infer": _infer,
    "replay": _replay,
    "record": _record,
}
"""What each command (other than the node commands) does with its parsed arguments."""
