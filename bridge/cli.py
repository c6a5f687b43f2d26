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

from .errors import BridgeError
from .session import SessionSettings
from .stopping import stop_on_signals, wait_for_stop

log = logging.getLogger("toyroom")


def add_zenoh_args(parser: argparse.ArgumentParser, *, world: bool = True) -> None:
    """Add the flags that choose the world and override the Zenoh session."""
    group = parser.add_argument_group("network (default: loopback only, no multicast)")
    if world:
        group.add_argument("--world", default="default", help="world name (default: %(default)s)")
    group.add_argument("--zenoh-config", type=Path, help="a Zenoh JSON5 config file to start from")
    group.add_argument("--mode", choices=("peer", "client", "router"), help="Zenoh mode (default: peer)")
    group.add_argument(
        "--listen", action="append", metavar="ENDPOINT", help="listen endpoint, e.g. tcp/127.0.0.1:7447"
    )
    group.add_argument(
        "--connect", action="append", metavar="ENDPOINT", help="connect endpoint (a router or peer)"
    )


def settings_from_args(args: argparse.Namespace) -> SessionSettings:
    """The session settings the network flags ask for."""
    return SessionSettings(
        mode=args.mode,
        listen=tuple(args.listen) if args.listen else None,
        connect=tuple(args.connect) if args.connect else None,
        config_file=args.zenoh_config,
    )


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
    from .router import run_router

    stop = threading.Event()
    stop_on_signals(stop)
    run_router(listen, config_file=config_file, stop=stop)
    return 0


def eval_main(episodes: int, seed: int, workers: int, backend: str, out: Path) -> int:
    """Run the evaluation with a progress bar and print the metrics."""
    from rich.console import Console
    from rich.markdown import Markdown
    from rich.progress import Progress

    from .evalreport import report
    from .evaluate import evaluate

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
    from .mcaprec import McapRecorder
    from .node import Bridge

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
    from .conformance import check_engine
    from .node import Bridge

    with Bridge(world, settings) as bridge:
        results = check_engine(bridge, timeout)
    for result in results:
        print(result.line())
    failed = [r for r in results if not r.passed]
    print(f"{len(results) - len(failed)} passed, {len(failed)} failed")
    return 1 if failed else 0


def doctor_main(world: str, settings: SessionSettings) -> int:
    """Check the installation end to end; see :mod:`bridge.doctor`."""
    from .doctor import run_doctor

    return run_doctor(world, settings)


NODES = {"sim": "sim2d", "brain": "brain", "view": "bridge.view"}
"""Subcommands that run a node package as its own process (``toyroom sim`` -> ``python -m sim2d``)."""


def exec_node(package: str, argv: Sequence[str]) -> int:
    """Replace this process with ``python -m package argv...`` (signals go straight to it)."""
    os.execv(sys.executable, [sys.executable, "-m", package, *argv])
    return 0  # pragma: no cover - execv does not return


def build_parser() -> argparse.ArgumentParser:
    """The argument parser of ``toyroom``."""
    parser = argparse.ArgumentParser(
        prog="toyroom", description="Theory-of-Mind robot brain, 2D engine and their Zenoh wire."
    )
    parser.add_argument("--log-level", default="INFO", help="logging level (default: %(default)s)")
    commands = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    schema = commands.add_parser("schema", help="write the JSON Schemas into protocol/schema/")
    schema.add_argument("--check", action="store_true", help="exit 1 when the checked-in schemas are stale")
    schema.add_argument("--dir", type=Path, help="schema directory (default: the package's)")

    router = commands.add_parser("router", help="run a Zenoh router for multi-machine setups")
    router.add_argument(
        "--listen", action="append", metavar="ENDPOINT", help="endpoint (default: tcp/127.0.0.1:7447)"
    )
    router.add_argument("--zenoh-config", type=Path, help="a Zenoh JSON5 config file to start from")

    for name, package in NODES.items():
        commands.add_parser(name, help=f"run {package} (`toyroom {name} --help` for its options)")

    run = commands.add_parser(
        "run", help="run an engine and the brain together, in lock-step, and keep the results"
    )
    run.add_argument("--scenario", default="paper-robot", help="scenario (default: %(default)s)")
    run.add_argument("--out", type=Path, default=Path("out"), help="results directory (default: %(default)s)")
    run.add_argument("--seed", type=int, default=0)
    run.add_argument("--observer", choices=("btom", "truebelief", "perceptonly"), default="btom")
    run.add_argument("--timeout", type=float, default=10.0, help="seconds per lock-step request")
    run.add_argument("--robot", choices=("act", "observe"), help="override whether the robot acts")
    run.add_argument(
        "--engine",
        choices=("sim2d", "grid"),
        default="sim2d",
        help="sim2d (pymunk) or grid (the example engine in examples/grid_engine/); default: %(default)s",
    )
    run.add_argument("--no-live", action="store_true", help="no live table (only the final one)")
    run.add_argument("--record", type=Path, metavar="FILE.mcap", help="also record every message to MCAP")
    run.add_argument("--view", action="store_true", help="also open the meshcat live view")

    replaying = commands.add_parser(
        "replay", help="republish an MCAP recording so brains and viewers run on it"
    )
    replaying.add_argument("file", type=Path, metavar="FILE.mcap")
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
        help="first wait up to S seconds for a subscriber",
    )
    add_zenoh_args(replaying)

    record = commands.add_parser("record", help="record every message of a world to MCAP until interrupted")
    record.add_argument("file", type=Path, metavar="FILE.mcap")
    add_zenoh_args(record)
    add_zenoh_args(run)
    run.set_defaults(world=None)

    infer = commands.add_parser("infer", help="infer minds from a recorded trace.jsonl (no engine needed)")
    infer.add_argument("trace", type=Path)
    infer.add_argument("--out", type=Path, required=True)
    infer.add_argument("--observer", choices=("btom", "truebelief", "perceptonly"), default="btom")

    bench = commands.add_parser("bench", help="measure the transport, lock-step and brain speeds in one run")
    bench.add_argument("--quick", action="store_true")
    bench.add_argument("--out", type=Path, default=Path("out/bench"))

    evaluation = commands.add_parser(
        "eval", help="measure the brain on random episodes with simulated people"
    )
    evaluation.add_argument("--episodes", type=int, default=40)
    evaluation.add_argument("--seed", type=int, default=1)
    evaluation.add_argument(
        "--workers", type=int, default=2, help="episodes at a time (default: %(default)s)"
    )
    evaluation.add_argument("--backend", choices=("local", "ray"), default="local")
    evaluation.add_argument("--out", type=Path, default=Path("out/eval"))

    conform = commands.add_parser("conform", help="check that the engine serving a world speaks the protocol")
    conform.add_argument(
        "--timeout", type=float, default=5.0, help="seconds per request (default: %(default)s)"
    )
    add_zenoh_args(conform)

    doctor = commands.add_parser(
        "doctor", help="check the install: schemas, and every message over loopback Zenoh"
    )
    add_zenoh_args(doctor)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Entry point of the ``toyroom`` console script."""
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv and argv[0] in NODES:
        return exec_node(NODES[argv[0]], argv[1:])
    args = build_parser().parse_args(argv)
    logging.basicConfig(
        level=getattr(logging, str(args.log_level).upper(), logging.INFO),
        format="%(asctime)s %(levelname)s %(name)s: %(message)s",
    )
    try:
        if args.command == "schema":
            return schema_main(args.check, args.dir)
        if args.command == "router":
            from .router import DEFAULT_ROUTER_ENDPOINT

            default = [] if args.zenoh_config else [DEFAULT_ROUTER_ENDPOINT]  # a config file says where
            return router_main(args.listen or default, args.zenoh_config)
        if args.command == "doctor":
            return doctor_main(args.world, settings_from_args(args))
        if args.command == "run":
            from .launch import RunConfig, run

            config = RunConfig(
                scenario=args.scenario,
                out=args.out,
                seed=args.seed,
                observer=args.observer,
                world=args.world if args.world != "default" else None,
                timeout=args.timeout,
                robot=args.robot,
                engine=args.engine,
                live=False if args.no_live else None,
                record=args.record,
                view=args.view,
            )
            return run(config, settings_from_args(args))
        if args.command == "bench":
            suite = Path(__file__).resolve().parents[1] / "bench" / "suite.py"
            quick = ["--quick"] if args.quick else []
            os.execv(sys.executable, [sys.executable, str(suite), *quick, "--out", str(args.out)])
        if args.command == "eval":
            return eval_main(args.episodes, args.seed, args.workers, args.backend, args.out)
        if args.command == "conform":
            return conform_main(args.world, settings_from_args(args), args.timeout)
        if args.command == "infer":
            extra = ["--observer", args.observer]
            trace = args.trace
            if trace.suffix == ".mcap":
                from .mcaprec import mcap_to_trace

                args.out.mkdir(parents=True, exist_ok=True)
                converted = args.out / "trace.jsonl"
                mcap_to_trace(trace, converted)
                trace = converted
            return exec_node("brain", ["infer", str(trace), "--out", str(args.out), *extra])
        if args.command == "replay":
            from .node import Bridge
            from .replay import replay

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
        if args.command == "record":
            return record_main(args.world, settings_from_args(args), args.file)
    except (BridgeError, ProtocolErrorBase) as err:
        print(f"toyroom {args.command}: {err}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        return 130
    raise AssertionError(f"unhandled command {args.command}")  # argparse rejects others


if __name__ == "__main__":
    sys.exit(main())
