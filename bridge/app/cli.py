"""The ``toyroom`` command line.

Each subcommand is a small typed function; ``main()`` parses the arguments and dispatches.
Nodes (engine, brain, viewer) are started as their own processes by the commands that
need them; this module never imports ``sim2d`` or ``brain``.
"""

from __future__ import annotations

import argparse
import logging
import os
import sys
import threading
from collections.abc import Sequence
from pathlib import Path

from protocol import Error as ProtocolErrorBase
from protocol import Observer

from ..errors import BridgeError
from ..flags import (
    PROG_ENV,
    HelpFormatter,
    configure_logging,
    log_level,
)
from ..session import SessionSettings, add_network_args, settings_from_args
from ..stopping import stop_on_signals, wait_for_stop

log = logging.getLogger("toyroom")


def schema_main(check: bool, directory: Path | None = None) -> int:
    """Write the JSON Schemas, or with ``check`` report stale ones and return 1."""
    from protocol.schema import SCHEMA_DIR, stale_schemas, write_schemas

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
    """Run a Zenoh router until interrupted."""
    from ..router import run_router

    stop = threading.Event()
    stop_on_signals(stop)
    run_router(listen, config_file=config_file, stop=stop)
    return 0


def eval_main(episodes: int, seed: int, workers: int, backend: str, out: Path) -> int:
    """Run the evaluation with a progress bar and print the metrics."""
    from rich.console import Console
    from rich.markdown import Markdown
    from rich.progress import Progress

    from ..evaluation.episodes import evaluate
    from ..evaluation.report import report

    with Progress() as bar:
        task = bar.add_task(f"{episodes} episodes", total=episodes)
        metrics = evaluate(
            episodes, seed, out, workers=workers, backend=backend, progress=lambda n: bar.advance(task, n)
        )
    Console().print(Markdown(report(metrics)))
    print(f"wrote {out / 'metrics.json'} and {out / 'report.md'}")
    return 0


def record_main(world: str, settings: SessionSettings, path: Path) -> int:
    """Record every message of ``world`` to ``path`` until SIGINT or SIGTERM."""
    from ..bridge import Bridge
    from ..recording.mcap import McapRecorder

    stop = threading.Event()
    stop_on_signals(stop)
    with Bridge(world, settings) as bridge, McapRecorder(bridge, path) as recorder:
        print(f"toyroom record: world '{world}' to {path}", flush=True)
        wait_for_stop(stop)
        count = recorder.count
    print(f"toyroom record: {count} messages in {path}")
    return 0


def conform_main(world: str, settings: SessionSettings, timeout: float) -> int:
    """Run the conformance kit against the engine of ``world``; 1 when a check fails."""
    from ..bridge import Bridge
    from ..conformance.checks import check_engine

    with Bridge(world, settings) as bridge:
        results = check_engine(bridge, timeout)
    for result in results:
        print(result.line())
    failed = [r for r in results if not r.passed]
    print(f"{len(results) - len(failed)} passed, {len(failed)} failed")
    return 1 if failed else 0


def doctor_main(world: str, settings: SessionSettings) -> int:
    """Check the installation end to end; see :mod:`bridge.app.doctor`."""
    from .doctor import run_doctor

    return run_doctor(world, settings)


NODES = {
    "sim": ("sim2d", ()),
    "brain": ("brain", ()),
    "view": ("bridge.view", ()),
    "generate": ("sim2d", ("generate",)),
}
"""Commands that run a node package as its own process (``toyroom sim`` -> ``python -m
sim2d``, ``toyroom generate`` -> ``python -m sim2d generate``), with their options."""

NODE_HELP = {
    "sim": "run the sim2d engine node (pymunk) until interrupted",
    "brain": "run the brain node (inference and robot) against any engine of the world",
    "view": "the meshcat live view of a world (prints its URL; --screenshot FILE.png)",
    "generate": "write a random episode (and its map): --map M --seed S --out DIR, or --rooms R --items K",
}


def exec_node(command: str, argv: Sequence[str], prog: str | None = None) -> int:
    """Replace this process with the node of ``command`` (signals go straight to it); its
    help and errors name ``prog`` (default: ``toyroom COMMAND``)."""
    package, leading = NODES[command]
    os.environ[PROG_ENV] = prog or f"toyroom {command}"
    os.execv(sys.executable, [sys.executable, "-m", package, *leading, *argv])
    return 0  # pragma: no cover - execv does not return


def global_parser() -> argparse.ArgumentParser:
    """The flags ``toyroom`` takes before or after any command name."""
    parser = argparse.ArgumentParser(add_help=False, allow_abbrev=False)
    parser.add_argument(
        "--log-level",
        type=log_level,
        metavar="LEVEL",
        help="DEBUG, INFO, WARNING or ERROR (default: INFO here, WARNING in the nodes a command starts)",
    )
    return parser


def _observer_arg(parser: argparse.ArgumentParser, help: str) -> None:
    parser.add_argument("--observer", choices=Observer.names(), default=Observer.BTOM.value, help=help)


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of ``toyroom`` (node commands are listed, their options are the node's)."""
    parser = argparse.ArgumentParser(
        prog="toyroom",
        description="Theory-of-Mind robot brain, 2D engine and their Zenoh wire.",
        parents=[global_parser()],
        formatter_class=HelpFormatter,
    )
    commands = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")
    shared = argparse.ArgumentParser(add_help=False)
    shared.add_argument("--log-level", type=log_level, default=argparse.SUPPRESS, help=argparse.SUPPRESS)

    def command(name: str, help: str) -> argparse.ArgumentParser:
        return commands.add_parser(
            name, help=help, description=help, parents=[shared], formatter_class=HelpFormatter
        )

    schema = command("schema", "write the JSON Schemas into protocol/schema/")
    schema.add_argument("--check", action="store_true", help="exit 1 when the checked-in schemas are stale")
    schema.add_argument("--dir", type=Path, help="schema directory (default: the package's)")

    router = command("router", "run a Zenoh router for multi-machine setups")
    router.add_argument(
        "--listen", action="append", metavar="ENDPOINT", help="endpoint (default: tcp/127.0.0.1:7447)"
    )
    router.add_argument("--zenoh-config", type=Path, help="a Zenoh JSON5 config file to start from")

    for name, text in NODE_HELP.items():
        commands.add_parser(name, help=f"{text} (`toyroom {name} --help`)", add_help=False)

    run = command("run", "run an engine and the brain together, in lock-step, and keep the results")
    run.add_argument("--scenario", default="paper-robot", help="bundled scenario name or .toml path")
    run.add_argument("--out", type=Path, default=Path("out"), help="results directory")
    run.add_argument("--seed", type=int, default=0, help="episode seed (the engine's random draws)")
    _observer_arg(run, "the brain's person model")
    run.add_argument(
        "--shadow",
        choices=Observer.names(),
        action="append",
        default=[],
        help="also run this observer on the same ticks, its minds in OUT/minds-NAME.jsonl (repeatable)",
    )
    run.add_argument("--timeout", type=float, default=10.0, help="seconds per lock-step request")
    run.add_argument(
        "--robot", choices=("act", "observe"), help="override whether the robot acts (default: the scene's)"
    )
    run.add_argument(
        "--engine",
        choices=("sim2d", "grid"),
        default="sim2d",
        help="sim2d (pymunk) or grid (the example engine in examples/grid_engine/, source checkout only)",
    )
    run.add_argument("--no-live", action="store_true", help="no live table (only the final one)")
    run.add_argument("--record", type=Path, metavar="FILE.mcap", help="also record every message to MCAP")
    run.add_argument("--view", action="store_true", help="also open the meshcat live view")
    add_network_args(run)
    run.set_defaults(world=None)

    replaying = command("replay", "republish an MCAP recording so brains and viewers run on it")
    replaying.add_argument("file", type=Path, metavar="FILE.mcap", help="the recording")
    replaying.add_argument("--speed", type=float, default=1.0, help="times real time; 0: as fast as possible")
    replaying.add_argument(
        "--until-tick", type=int, help="stop after this tick (and keep serving the handshake)"
    )
    replaying.add_argument("--hold", action="store_true", help="keep serving the handshake until interrupted")
    replaying.add_argument(
        "--wait-subscribers",
        type=float,
        default=0.0,
        metavar="S",
        help="first wait up to S s for a subscriber",
    )
    add_network_args(replaying)

    record = command("record", "record every message of a world to MCAP until interrupted")
    record.add_argument("file", type=Path, metavar="FILE.mcap", help="the recording to write")
    add_network_args(record)

    infer = command("infer", "infer minds from a recording (trace.jsonl or .mcap), no engine needed")
    infer.add_argument("trace", type=Path, help="a trace.jsonl or .mcap written by toyroom run")
    infer.add_argument("--out", type=Path, required=True, help="directory for mind.csv, figures, report.md")
    _observer_arg(infer, "the person model to infer with")

    bench = command("bench", "measure the transport, lock-step and brain speeds in one run (source checkout)")
    bench.add_argument("--quick", action="store_true", help="fewer repeats and houses (under 3 minutes)")
    bench.add_argument(
        "--out", type=Path, default=Path("out/bench"), help="directory for bench.json and plots"
    )

    evaluation = command("eval", "measure the brain on random episodes with simulated people")
    evaluation.add_argument("--episodes", type=int, default=40, help="how many episodes")
    evaluation.add_argument("--seed", type=int, default=1, help="sweep seed (episode i gets 1000 x seed + i)")
    evaluation.add_argument("--workers", type=int, default=2, help="episodes at a time")
    evaluation.add_argument(
        "--backend", choices=("local", "ray"), default="local", help="local threads, or Ray tasks"
    )
    evaluation.add_argument(
        "--out", type=Path, default=Path("out/eval"), help="directory for metrics and report"
    )

    conform = command("conform", "check that the engine serving a world speaks the protocol")
    conform.add_argument("--timeout", type=float, default=5.0, help="seconds per request")
    add_network_args(conform)

    doctor = command("doctor", "check the install: schemas, and every message over loopback Zenoh")
    add_network_args(doctor)
    return parser


def _schema(args: argparse.Namespace) -> int:
    return schema_main(args.check, args.dir)


def _router(args: argparse.Namespace) -> int:
    from ..router import DEFAULT_ROUTER_ENDPOINT

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
        observer=args.observer,
        world=args.world if args.world != "default" else None,
        timeout=args.timeout,
        log_level=args.log_level or "WARNING",
        robot=args.robot,
        engine=args.engine,
        live=False if args.no_live else None,
        record=args.record,
        view=args.view,
        shadows=tuple(args.shadow),
    )
    return run(config, settings_from_args(args))


def _bench(args: argparse.Namespace) -> int:
    from .processes import source_file

    suite = source_file("bench/suite.py")
    quick = ["--quick"] if args.quick else []
    os.execv(sys.executable, [sys.executable, str(suite), *quick, "--out", str(args.out)])
    return 0  # pragma: no cover - execv does not return


def _eval(args: argparse.Namespace) -> int:
    return eval_main(args.episodes, args.seed, args.workers, args.backend, args.out)


def _conform(args: argparse.Namespace) -> int:
    return conform_main(args.world, settings_from_args(args), args.timeout)


def _infer(args: argparse.Namespace) -> int:
    trace = args.trace
    if trace.suffix == ".mcap":
        from ..recording.mcap import mcap_to_trace

        args.out.mkdir(parents=True, exist_ok=True)
        converted = args.out / "trace.jsonl"
        mcap_to_trace(trace, converted)
        trace = converted
    levels = ["--log-level", args.log_level] if args.log_level else []
    return exec_node(
        "brain", ["infer", str(trace), "--out", str(args.out), "--observer", args.observer, *levels]
    )


def _replay(args: argparse.Namespace) -> int:
    from ..bridge import Bridge
    from ..recording.replay import replay

    stop = threading.Event()
    stop_on_signals(stop)
    with Bridge(args.world, settings_from_args(args)) as bridge:
        sent = replay(
            bridge,
            args.file,
            speed=args.speed,
            stop=stop,
            until_tick=args.until_tick,
            wait_subscribers=args.wait_subscribers,
        )
        print(f"toyroom replay: {sent} messages from {args.file} on world '{args.world}'", flush=True)
        if args.hold:
            wait_for_stop(stop)
    return 0


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


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``toyroom`` console script. Global flags (``--log-level``) may
    come before or after the command name."""
    argv = list(sys.argv[1:] if argv is None else argv)
    flags, rest = global_parser().parse_known_args(argv)
    if rest and rest[0] in NODES:
        levels = ["--log-level", flags.log_level] if flags.log_level else []
        return exec_node(rest[0], [*rest[1:], *levels])
    args = build_parser().parse_args(argv)
    configure_logging(args.log_level or "INFO")
    try:
        return COMMANDS[args.command](args)
    except (BridgeError, ProtocolErrorBase) as err:
        print(f"toyroom {args.command}: {err}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return 130


if __name__ == "__main__":
    sys.exit(main())
