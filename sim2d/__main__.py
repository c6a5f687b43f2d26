"""``python -m sim2d --scenario NAME [--world W] [--lockstep | --realtime RATE]``: run the
engine node until interrupted (``toyroom sim`` starts this as a process); ``python -m sim2d
generate ...`` (``toyroom generate``) writes a random episode; ``python -m sim2d scene
--scenario NAME`` prints its protocol scene (what ``python -m brain plan`` reads)."""

from __future__ import annotations

import argparse
import signal
import sys
from collections.abc import Sequence
from pathlib import Path

import msgspec

from bridge import Bridge, BridgeError
from bridge.flags import (
    add_log_level,
    command_parser,
    configure_logging,
    out_file_problem,
    out_folder_problem,
)
from bridge.recording.mcap import McapRecorder
from bridge.session import add_network_args, settings_from_args, world_problem
from protocol import MAX_TICKS, ClockMode, EpisodeKind, EpisodeSpec, Minds, Morning, RobotMode, TaskKind

from .engine import Engine
from .errors import Sim2dError
from .node import EngineNode
from .people.policytable import load_policy_table
from .scenario.scenario import scenario_names


def build_parser() -> argparse.ArgumentParser:
    """The parser of ``python -m sim2d``: the engine node's options."""
    parser = command_parser("python -m sim2d", "The pymunk engine node, until interrupted.")
    parser.add_argument(
        "--scenario", default="paper-robot", help="scenario name or .toml path (default: %(default)s)"
    )
    parser.add_argument("--seed", type=int, default=0, help="episode seed (default: %(default)s)")
    clock = parser.add_mutually_exclusive_group()
    clock.add_argument("--lockstep", action="store_true", help="advance only on step requests (the default)")
    clock.add_argument("--realtime", type=float, metavar="RATE", help="free-run at RATE x wall-clock speed")
    parser.add_argument("--robot", choices=RobotMode.names(), help="override the scenario's robot mode")
    parser.add_argument("--list", action="store_true", help="list the bundled scenarios and exit")
    parser.add_argument(
        "--record", type=Path, metavar="FILE.mcap", help="record every message of the world to MCAP"
    )
    parser.add_argument(
        "--policy",
        type=Path,
        metavar="FILE.npz",
        help='the brain\'s planner table (`python -m brain plan`) for people with planner = "model"',
    )
    parser.add_argument(
        "--puppet",
        action="append",
        default=[],
        metavar="PERSON",
        help="drive this person from person/PERSON/command (toyroom play) instead of its script (repeatable)",
    )
    add_log_level(parser)
    add_network_args(parser)
    return parser


def scene_parser() -> argparse.ArgumentParser:
    """The parser of ``python -m sim2d scene``."""
    parser = command_parser("python -m sim2d scene", "Print a scenario's protocol scene as JSON.")
    parser.add_argument("--scenario", required=True, help="scenario name or .toml path")
    parser.add_argument("--seed", type=int, default=0, help="episode seed (default: %(default)s)")
    parser.add_argument(
        "--study",
        action="store_true",
        help='print {"scene": the scene, "study": the scenario\'s [study] section or null} instead',
    )
    return parser


def scene_main(argv: Sequence[str]) -> int:
    """``python -m sim2d scene --scenario S``: the scene ``engine/info`` would carry, on stdout
    (``--study``: with the scenario's ``[study]`` section, :class:`protocol.Study`)."""
    args = scene_parser().parse_args(argv)
    try:
        engine = Engine(args.scenario, seed=args.seed, check_policy=False)
    except Sim2dError as err:
        print(f"sim2d: {err}", file=sys.stderr)
        return 2
    scene = engine.scene()
    shown = {"scene": scene, "study": engine.scenario.study} if args.study else scene
    print(msgspec.json.encode(shown).decode())
    return 0


def export_main(argv: Sequence[str]) -> int:
    """``python -m sim2d export --scenario S [--out FILE]``: the scenario as one JSON document."""
    from .export import export

    parser = command_parser("python -m sim2d export", "Write a scenario as JSON (for the C# engine).")
    parser.add_argument("--scenario", required=True, help="scenario name or .toml path")
    parser.add_argument("--out", type=Path, help="the JSON file (default: standard output)")
    args = parser.parse_args(argv)
    if args.out is not None and (problem := out_file_problem(args.out)) is not None:
        print(f"{parser.prog}: {problem}", file=sys.stderr)
        return 2
    try:
        text = msgspec.json.format(msgspec.json.encode(export(args.scenario)), indent=1).decode()
    except Sim2dError as err:
        print(f"sim2d: {err}", file=sys.stderr)
        return 2
    if args.out is None:
        print(text)
    else:
        args.out.parent.mkdir(parents=True, exist_ok=True)
        args.out.write_text(text + "\n", encoding="utf-8")
    return 0


def generate_parser() -> argparse.ArgumentParser:
    """``python -m sim2d generate``'s options."""
    from .generation.episodes import ITEM_SHAPES, KINDS, MAPS, MINDS
    from .generation.tasks import TASKS

    parser = command_parser(
        "python -m sim2d generate",
        "Write a random episode (gen-MAP-sSEED.toml, and its map when generated) and print its path.",
    )
    parser.add_argument("--map", choices=sorted(MAPS), default="paper", help="the map to draw the episode on")
    parser.add_argument("--rooms", type=int, help="generate a house of this many rooms (instead of --map)")
    parser.add_argument(
        "--items", type=int, default=3, help=f"items on a --rooms house (1 to {len(ITEM_SHAPES)})"
    )
    parser.add_argument("--seed", type=int, default=0, help="the episode's seed (items, people, their minds)")
    parser.add_argument(
        "--episodes",
        nargs="+",
        metavar="MAP:SEED",
        help="write each of these episodes (instead of --map and --seed) and print their paths, one a line",
    )
    parser.add_argument(
        "--max-ticks", type=int, default=MAX_TICKS, help="the episode ends after this many ticks"
    )
    parser.add_argument(
        "--minds",
        choices=MINDS,
        default="simple",
        help="simple: people perceive exactly and keep to themselves; rich: they forget, overlook, "
        "gossip and wander (drawn from the seed); model: they act by the brain's planner "
        "(the engine then needs --policy)",
    )
    parser.add_argument(
        "--kind",
        choices=KINDS,
        default="everyday",
        help="everyday: random habits; tasks: built around the robot's jobs (an item moved while its "
        "owner is away, hidden where they will look last, or wanted by both; a wrong place told, "
        "overlooked or remembered)",
    )
    parser.add_argument(
        "--tasks",
        type=_task_kinds,
        default=None,
        help="with --kind tasks: the task kinds to draw from in turn by seed, comma-separated "
        f"({', '.join(TASKS)}; default: all)",
    )
    parser.add_argument(
        "--autonomy",
        type=_override,
        action="append",
        default=[],
        metavar="NAME=VALUE",
        help="set one of the people's [autonomy] settings in every episode written, over the drawn "
        "one (a TOML value: replan_lag=[100000,100000], search='nearest'); repeatable",
    )
    parser.add_argument(
        "--day",
        type=int,
        help="write day D of the household of each episode's seed (named EPISODE-dD; day 1 is the "
        "episode itself, with a [household] table); a later day needs --morning",
    )
    parser.add_argument(
        "--morning",
        type=Path,
        metavar="FILE.json",
        help="with --day D > 1: where the day before ended (protocol.Morning as JSON: items, the "
        "people's sure beliefs and favourites, and the household and map it is of, checked "
        "strictly against this household's); the night's changes are drawn on top",
    )
    parser.add_argument("--out", type=Path, required=True, help="directory for the scenario (and map) files")
    add_log_level(parser, "WARNING")
    return parser


def _morning(parser: argparse.ArgumentParser, path: Path | None) -> Morning | None:
    """``--morning``'s file, read and checked (a bad one is a usage error naming it)."""
    if path is None:
        return None
    try:
        return msgspec.json.decode(path.read_bytes(), type=Morning)
    except (OSError, msgspec.DecodeError, msgspec.ValidationError) as err:
        parser.error(f"--morning {path}: {err}")


def generate_main(argv: Sequence[str]) -> int:
    """``python -m sim2d generate --map M --seed S --out DIR``: write a random episode
    (``--rooms R --items K``: on a new house of that size instead)."""
    from .errors import ScenarioError
    from .generation.episodes import write_episode, write_house_episode
    from .generation.mornings import MorningError

    parser = generate_parser()
    args = parser.parse_args(argv)
    if (problem := out_folder_problem(args.out)) is not None:
        print(f"{parser.prog}: {problem}", file=sys.stderr)
        return 2
    autonomy = tuple(f"{name}={value}" for name, value in args.autonomy)
    spec = EpisodeSpec(Minds(args.minds), EpisodeKind(args.kind), args.max_ticks, args.tasks or (), autonomy)
    days = {"day": args.day, "morning": _morning(parser, args.morning)}
    if args.rooms is not None and args.day is not None:
        parser.error("--day: households are drawn on --map or --episodes maps, not --rooms houses")
    try:
        if args.rooms is not None:
            print(write_house_episode(args.out, args.rooms, args.items, args.seed, spec))
        elif args.episodes:
            for map_name, seed in _episode_list(parser, args.episodes):
                print(write_episode(args.out, map_name, seed, spec, **days))
        else:
            print(write_episode(args.out, args.map, args.seed, spec, **days))
    except MorningError as err:  # one line, naming the file and what does not fit
        print(f"{parser.prog}: --morning {args.morning}: {err}", file=sys.stderr)
        return 2
    except (ValueError, ScenarioError) as err:
        parser.error(str(err))
    return 0


def _override(text: str) -> tuple[str, str]:
    """``--autonomy``'s ``NAME=VALUE``, checked (a bad one is a usage error naming it)."""
    from .generation.overrides import parse_override

    try:
        return parse_override(text)
    except ValueError as err:
        raise argparse.ArgumentTypeError(str(err)) from None


def _task_kinds(text: str) -> tuple[TaskKind, ...]:
    """``--tasks``'s comma-separated kinds, checked (a bad one is a usage error naming it)."""
    from .generation.tasks import check_kinds

    try:
        return check_kinds([kind.strip() for kind in text.split(",") if kind.strip()])
    except ValueError as err:
        raise argparse.ArgumentTypeError(str(err)) from None


def _episode_list(parser: argparse.ArgumentParser, entries: Sequence[str]) -> list[tuple[str, int]]:
    """``MAP:SEED`` entries as ``(map, seed)``; a bad one is a usage error that names it."""
    from .generation.episodes import MAPS

    out = []
    for entry in entries:
        map_name, _, seed = entry.partition(":")
        if map_name not in MAPS or not seed.lstrip("-").isdigit():
            parser.error(f"--episodes: {entry!r} is not MAP:SEED with MAP one of {', '.join(sorted(MAPS))}")
        out.append((map_name, int(seed)))
    return out


def main(argv: Sequence[str] | None = None) -> int:
    """Run the engine node (or ``generate``, ``scene``, ``export``) on ``argv``; the exit status."""
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv and argv[0] == "generate":
        return generate_main(argv[1:])
    if argv and argv[0] == "scene":
        return scene_main(argv[1:])
    if argv and argv[0] == "export":
        return export_main(argv[1:])
    args = build_parser().parse_args(argv)
    configure_logging(args.log_level)
    if args.list:
        print("\n".join(scenario_names()))
        return 0
    if args.realtime is not None and args.realtime <= 0:
        print("sim2d: --realtime RATE must be > 0", file=sys.stderr)
        return 2
    if (problem := world_problem(args.world)) is not None:
        print(f"sim2d: {problem}", file=sys.stderr)
        return 2
    try:
        policy = load_policy_table(args.policy) if args.policy else None
        robot = RobotMode(args.robot) if args.robot else None
        engine = Engine(args.scenario, seed=args.seed, robot=robot, policy=policy)
        clock = ClockMode.REALTIME if args.realtime is not None else ClockMode.LOCKSTEP
        node = EngineNode(
            engine,
            Bridge(args.world, settings_from_args(args)),
            clock=clock,
            rate=args.realtime or 1.0,
            puppets=tuple(args.puppet),
        )
    except (Sim2dError, BridgeError) as err:
        print(f"sim2d: {err}", file=sys.stderr)
        return 2
    for sig in (signal.SIGINT, signal.SIGTERM):
        signal.signal(sig, lambda *_: node.stop())
    print(f"sim2d: scenario '{engine.scenario.name}' on world '{args.world}' ({clock.value})", flush=True)
    recorder = McapRecorder(node.bridge, args.record, info=node.info()) if args.record else None
    node.wait()
    if recorder is not None:
        recorder.close()
    node.close()
    if recorder is not None and recorder.error is not None:  # a full disk: the rest is lost
        print(f"sim2d: --record: {recorder.error}", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
