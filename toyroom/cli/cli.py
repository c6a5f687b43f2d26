"""The ``toyroom`` command line: its parser (one builder per command) and ``main()``, which
dispatches to :mod:`toyroom.cli.commands`. Global flags may come before or after the command
name; node commands (``toyroom sim``...) are handed to the node with their options."""

from __future__ import annotations

import argparse
import logging
import sys
from collections.abc import Callable, Sequence
from pathlib import Path

from bridge.errors import BridgeError
from bridge.flags import (
    HelpFormatter,
    add_settings_args,
    configure_logging,
    log_level,
    non_negative_int,
    out_file_problem,
    out_folder_problem,
)
from bridge.recording.atomic import OutputError, disk_full, output_error
from bridge.session import add_network_args, world_problem
from protocol import OBSERVING, EpisodeKind, Minds, Observer, Perception, Policy, RobotMode, TaskKind
from protocol import Error as ProtocolErrorBase
from protocol.episodespec import MAX_TICKS

from .choicehelp import KIND_NOTES, MINDS_NOTES, PERCEPTION_NOTES, POLICY_NOTES, described
from .commands import BATCH, COMMANDS, NODES, exec_node
from .floors import time_problem
from .households import MAX_DAYS

log = logging.getLogger("toyroom")


NODE_HELP = {
    "sim": "run the sim2d engine node (pymunk) until interrupted",
    "brain": "run the brain node (inference and robot) against any engine of the world",
    "view": "the meshcat live view of a world (prints its URL; --screenshot FILE.png)",
    "gateway": "carry a world over a WebSocket for engines without Zenoh (Unity, C#): "
    "--world W [--listen ws://127.0.0.1:7448] [--token FILE]",
    "play": "serve a page where participants play one person of a scenario in their browser, each in a "
    "world of their own, recorded to MCAP: --scenario S --as A1 [--participants N] [--out DIR]",
    "generate": "write a random episode (and its map): --map M --seed S --out DIR, or --rooms R --items K",
    "export-scenario": "write a scenario as one JSON document for engines without TOML (the C# engine): "
    "--scenario NAME [--out FILE]",
    "fit": "fit the model's parameters to recorded runs (RECORDINGS... --params beta,hazard --out DIR), "
    "cross-validated by episode, and compare models by held-out log-likelihood",
    "memory": "the brain's memory of households across days: show FILE | forget FILE PERSON | "
    "export FILE [--out JSON] | import FILE JSON",
    "morning": "write a household's next morning from a finished run: RUN [--out FILE.json]",
    "rate": "serve a judgments page: participants watch recordings and rate beliefs and desires "
    "(RECORDINGS... --questions FILE.toml [--out FILE.csv] [--participants N])",
}


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


def _strict_arg(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--strict",
        action="store_true",
        help="refuse a cut-off or damaged recording (exit 1) instead of using the part before the "
        "break with a warning",
    )


Command = Callable[[str, str], argparse.ArgumentParser]
"""Adds a command (name, help) to ``toyroom``'s parser and returns its parser."""


def _schema_command(command: Command) -> None:
    """``toyroom schema``'s options."""
    schema = command("schema", "write the JSON Schemas into protocol/schema/")
    schema.add_argument("--check", action="store_true", help="exit 1 when the checked-in schemas are stale")
    schema.add_argument("--dir", type=Path, help="schema directory (default: the package's)")
    schema.add_argument(
        "--csharp",
        action="store_true",
        help="the C# SDK's message classes (clients/unity/Runtime/Protocol/Messages.g.cs) instead",
    )


def _router_command(command: Command) -> None:
    """``toyroom router``'s options."""
    router = command("router", "run a Zenoh router for multi-machine setups")
    router.add_argument(
        "--listen", action="append", metavar="ENDPOINT", help="endpoint (default: tcp/127.0.0.1:7447)"
    )
    router.add_argument("--zenoh-config", type=Path, help="a Zenoh JSON5 config file to start from")


def _run_command(command: Command) -> None:
    """``toyroom run``'s options."""
    run = command("run", "run an engine and the brain together, in lock-step, and keep the results")
    run.add_argument("--scenario", default="paper-robot", help="bundled scenario name or .toml path")
    run.add_argument("--out", type=Path, default=Path("out"), help="results directory")
    run.add_argument("--seed", type=int, default=0, help="episode seed (the engine's random draws)")
    _observer_arg(run, "the brain's person model")
    add_settings_args(run)
    run.add_argument(
        "--shadow",
        choices=Observer.names(),
        action="append",
        default=[],
        help="also run this observer on the same ticks, its minds in OUT/minds-NAME.jsonl (repeatable)",
    )
    run.add_argument(
        "--timeout", type=float, default=10.0, help="seconds per lock-step request (0: none; else >= 1)"
    )
    run.add_argument(
        "--robot", choices=RobotMode.names(), help="override whether the robot acts (default: the scene's)"
    )
    run.add_argument(
        "--engine",
        choices=("sim2d", "grid", "csharp", "godot"),
        default="sim2d",
        help="sim2d (pymunk), grid (examples/grid_engine/), csharp (the C# SDK's grid engine under "
        "Mono, through the gateway; needs mono-devel) or godot (the Godot add-on's sample under "
        "godot3-server, through the gateway); grid, csharp and godot need a source checkout",
    )
    run.add_argument(
        "--gateway",
        action="store_true",
        help="start `toyroom gateway` and connect the engine through it (a WebSocket instead of Zenoh; grid)",
    )
    run.add_argument("--no-live", action="store_true", help="no live table (only the final one)")
    run.add_argument("--record", type=Path, metavar="FILE.mcap", help="also record every message to MCAP")
    run.add_argument("--view", action="store_true", help="also open the meshcat live view")
    run.add_argument("--memory", type=Path, metavar="FILE", help="the brain's memory, as brain --memory")
    add_network_args(run)
    run.set_defaults(world=None)


def _replay_command(command: Command) -> None:
    """``toyroom replay``'s options."""
    replaying = command("replay", "republish an MCAP recording so brains and viewers run on it")
    replaying.add_argument("file", type=Path, metavar="FILE.mcap", help="the recording")
    _strict_arg(replaying)
    replaying.add_argument(
        "--speed", type=float, default=1.0, help="times real time (at least 0.001); 0: as fast as possible"
    )
    replaying.add_argument(
        "--until-tick",
        type=non_negative_int,
        help="stop after this tick, a whole number >= 0 (and keep serving the handshake)",
    )
    replaying.add_argument("--hold", action="store_true", help="keep serving the handshake until interrupted")
    replaying.add_argument(
        "--wait-subscribers",
        type=float,
        default=0.0,
        metavar="S",
        help="first wait up to S s (>= 0) for a subscriber",
    )
    add_network_args(replaying)


def _record_command(command: Command) -> None:
    """``toyroom record``'s options."""
    record = command("record", "record every message of a world to MCAP until interrupted")
    record.add_argument("file", type=Path, metavar="FILE.mcap", help="the recording to write")
    add_network_args(record)


def _infer_command(command: Command) -> None:
    """``toyroom infer``'s options."""
    infer = command("infer", "infer minds from a recording (trace.jsonl or .mcap), no engine needed")
    infer.add_argument("trace", type=Path, help="a trace.jsonl or .mcap written by toyroom run")
    infer.add_argument("--out", type=Path, required=True, help="directory for mind.csv, figures, report.md")
    _observer_arg(infer, "the person model to infer with")
    _strict_arg(infer)
    add_settings_args(infer)


def _bench_command(command: Command) -> None:
    """``toyroom bench``'s options."""
    bench = command("bench", "measure the transport, lock-step and brain speeds in one run")
    bench.add_argument("--quick", action="store_true", help="fewer repeats and houses (under 3 minutes)")
    bench.add_argument(
        "--memory",
        action="store_true",
        help="only the brain's peak resident memory with miss = 0.2 and an embodied robot on house-a "
        "and house-b task episodes (about 3 minutes)",
    )
    bench.add_argument(
        "--out", type=Path, default=Path("out/bench"), help="directory for bench.json and plots"
    )


def _eval_command(command: Command) -> None:
    """``toyroom eval``'s options."""
    evaluation = command("eval", "measure the brain on random episodes with simulated people")
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
        f"episode of its own; at most {MAX_DAYS}; above 1: no --batch; resumed a chain's day at a time)",
    )
    evaluation.add_argument(
        "--batch",
        type=int,
        help="at most this many episodes of a condition share one engine and one brain process "
        "per kind of run (each run still a fresh model and episode; 1: a process pair per run; "
        f"default: {BATCH}; refused with --days above 1)",
    )
    _eval_outputs(evaluation)
    add_settings_args(evaluation)


def _eval_outputs(evaluation: argparse.ArgumentParser) -> None:
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


def _conform_command(command: Command) -> None:
    """``toyroom conform``'s options."""
    conform = command("conform", "check that the engine serving a world speaks the protocol")
    conform.add_argument("--timeout", type=float, default=5.0, help="seconds per request (at least 1)")
    conform.add_argument(
        "--strict",
        action="store_true",
        help="fail on a skipped check too (one that applies to the engine but found nothing to exercise)",
    )
    add_network_args(conform)


def _doctor_command(command: Command) -> None:
    """``toyroom doctor``'s options."""
    doctor = command("doctor", "check the install: schemas, and every message over loopback Zenoh")
    add_network_args(doctor)


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

    _schema_command(command)
    _router_command(command)
    for name, text in NODE_HELP.items():
        commands.add_parser(name, help=f"{text} (`toyroom {name} --help`)", add_help=False)
    _run_command(command)
    _replay_command(command)
    _record_command(command)
    _infer_command(command)
    _bench_command(command)
    _eval_command(command)
    _conform_command(command)
    _doctor_command(command)
    return parser


FOLDER_OUT = ("run", "infer", "bench", "eval")
"""Commands whose ``--out`` is a folder (made when missing)."""


def argument_problem(args: argparse.Namespace) -> str | None:
    """What is wrong with arguments the parser let through (an ``--out`` that is a file, a
    recording to write that is a folder or in a missing one, a time flag below its floor,
    a world name that is none), in one line, or ``None``."""
    if getattr(args, "world", None) is not None and (problem := world_problem(args.world)) is not None:
        return problem
    if args.command in FOLDER_OUT and (problem := out_folder_problem(args.out)) is not None:
        return problem
    if args.command == "run" and args.record is not None:
        if (problem := out_file_problem(args.record, "--record", make_folder=False)) is not None:
            return problem
    if args.command == "record":
        return out_file_problem(args.file, "", make_folder=False)
    return time_problem(args)  # a time flag below its floor (:mod:`.floors`)


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
    if (problem := argument_problem(args)) is not None:
        print(f"toyroom {args.command}: {problem}", file=sys.stderr)
        return 2
    try:
        return COMMANDS[args.command](args)
    except (BridgeError, ProtocolErrorBase) as err:
        print(f"toyroom {args.command}: {err}", file=sys.stderr)
        return 2
    except OSError as err:  # a full disk writing the outputs: one line, nothing half written
        if not (isinstance(err, OutputError) or disk_full(err)):
            raise
        print(f"toyroom {args.command}: {output_error(err)}", file=sys.stderr)
        return 1
    except KeyboardInterrupt:
        return 130


if __name__ == "__main__":
    sys.exit(main())
