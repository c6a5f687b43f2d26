"""The brain's command line (``toyroom brain`` and ``toyroom infer`` start these).

- ``python -m brain [--world W] [--scenario S] [--seed N] [--out DIR] [--observer O]``:
  the live brain node, in lock-step with the world's engine, until the episode ends
  (``--episodes S1 S2 ...``: one episode of each scenario in turn, on the same engine;
  ``--serve``: one run per line of standard input, each line the run's options, for
  ``toyroom eval --days``, whose runs are known only as the one before ends).
- ``python -m brain infer TRACE --out DIR [--observer O]``: the same outputs from a
  recorded ``trace.jsonl``, with no engine.
- ``python -m brain check-settings [--settings FILE] [--set NAME=VALUE]...``: exit 0 when
  the settings are allowed, else 2 with one line naming the setting, its value and what is
  allowed (``toyroom run`` asks this before it starts any process).
- ``python -m brain plan --scene SCENE.json --out FILE.npz``: the planner's Q-values of a
  scene, for simulated people who act by the brain's planner (:mod:`brain.outputs.policytable`).
- ``python -m brain memory show|forget|export|import FILE ...`` (``toyroom memory``): the memory of
  households across days that ``--memory FILE`` keeps (:mod:`brain.memory.command`).
"""

from __future__ import annotations

import argparse
import json
import logging
import signal
import sys
from collections.abc import Iterable, Sequence
from contextlib import nullcontext
from pathlib import Path

import msgspec

from bridge import Bridge, BridgeError
from bridge.flags import (
    add_log_level,
    add_settings_args,
    command_parser,
    configure_logging,
    positive_int,
)
from bridge.processes import exit_with_parent
from bridge.recording.atomic import OutputError, write_text
from bridge.recording.mcap import McapRecorder
from bridge.recording.trace import read_trace
from bridge.session import add_network_args, settings_from_args, world_problem
from protocol import Error as ProtocolError
from protocol import Observer, RobotMode, Scene

from .errors import BrainError
from .memory import CHECKPOINT_TICKS, KEEP_DAYS, MemoryKeeper, open_memory
from .memory.command import memory_main, memory_parser
from .model.planner import use_store
from .model.revisions import SharedRevisions
from .model.size import check_model_size
from .node import BrainNode
from .outputs.policytable import write_policy_table
from .outputs.results import write_outputs
from .outputs.valuestore import ValueDirectory
from .robot.tree import RobotTree
from .settings import Settings, load_settings, settings_toml
from .tracking.tracker import MindTracker

OBSERVERS = Observer.names()
FINISHED = "brain: finished run"
"""What ``--serve`` writes on standard output once a run's outputs, run log and memory are
saved (with the run's number, from 1)."""


def run_parser() -> argparse.ArgumentParser:
    parser = command_parser(
        "python -m brain",
        "The Theory-of-Mind brain node, in lock-step with the world's engine (or free-running with a\n"
        "real-time one) until the episode ends\n"
        "(`python -m brain infer TRACE --out DIR`: the same outputs from a recording).",
    )
    chosen = parser.add_mutually_exclusive_group()
    chosen.add_argument(
        "--scenario",
        help="scenario to reset the engine to (default: lock-step, the engine's current one; "
        "real time, no reset: join the episode running)",
    )
    chosen.add_argument(
        "--episodes",
        nargs="+",
        metavar="SCENARIO",
        help="run one episode of each scenario in turn (each a fresh model), resetting the "
        "engine to it; --out, --shadow-out and --run-log then get a folder per episode, named "
        "by its scenario file's stem",
    )
    parser.add_argument("--seed", type=int, default=0, help="episode seed of the reset")
    parser.add_argument("--out", type=Path, help="write mind.csv, figures and report.md here at the end")
    parser.add_argument("--observer", choices=OBSERVERS, default=OBSERVERS[0], help="person model")
    parser.add_argument(
        "--timeout",
        type=float,
        default=10.0,
        help="seconds per lock-step request (real time: the wait for states); 0: no limit",
    )
    parser.add_argument(
        "--handshake-timeout", type=float, default=30.0, help="seconds to wait for the engine"
    )
    lost = "seconds a lost engine may stay gone before the run fails (exit 2; an evaluation runs it"
    lost += " again); 0, the default: wait however long (an engine at an editor's breakpoint)"
    parser.add_argument("--lost-timeout", type=non_negative_float, default=0.0, help=lost)
    parser.add_argument(
        "--max-ticks", type=int, help="stop after this many ticks even if the episode goes on"
    )
    parser.add_argument(
        "--robot",
        choices=RobotMode.names(),
        help="override whether the robot acts (default: as the scene says)",
    )
    parser.add_argument(
        "--shadow",
        choices=OBSERVERS,
        action="append",
        default=[],
        help="also run this observer on the same ticks, writing its minds to --shadow-out (repeatable)",
    )
    parser.add_argument(
        "--shadow-out", type=Path, default=Path("."), help="directory of the shadow minds-NAME.jsonl files"
    )
    parser.add_argument(
        "--run-log",
        type=Path,
        metavar="DIR",
        help="write every state and event handled (inputs.jsonl) and every mind published "
        "(minds-OBSERVER.jsonl) into DIR, for scoring the run afterwards",
    )
    parser.add_argument("--print-tree", action="store_true", help="print the robot's behaviour tree and exit")
    parser.add_argument(
        "--record", type=Path, metavar="FILE.mcap", help="record every message of the world to MCAP"
    )
    _memory_args(parser)
    _serve_arg(parser)
    parser.add_argument(
        "--values-cache",
        type=Path,
        metavar="DIR",
        help="keep solved Q-values in DIR and read them from there (brains sharing DIR solve each map once)",
    )
    add_settings_args(parser)
    add_log_level(parser)
    add_network_args(parser)
    return parser


def infer_parser() -> argparse.ArgumentParser:
    parser = command_parser("python -m brain infer", "Infer minds from a recorded trace.")
    parser.add_argument("trace", type=Path, help="a trace.jsonl written by `toyroom run`")
    parser.add_argument("--out", type=Path, required=True, help="directory for mind.csv, figures, report.md")
    parser.add_argument("--observer", choices=OBSERVERS, default=OBSERVERS[0], help="person model")
    parser.add_argument(
        "--note",
        default="",
        help="a paragraph for report.md, put first (toyroom infer: the recording was cut off or damaged)",
    )
    add_settings_args(parser)
    add_log_level(parser, "WARNING")
    return parser


def infer_main(trace_path: Path, out: Path, observer: Observer, settings: Settings, note: str = "") -> int:
    """Replay a trace through the inference and write the outputs (``note``: the report's
    first paragraph)."""
    trace = read_trace(trace_path)
    tracker = MindTracker(trace.info.scene, settings.model, observer, SharedRevisions())  # for branches
    for state, events in trace:
        tracker.observe(state, events)
    path = write_results(tracker, trace.info.scenario, out, settings, note)
    print(f"brain: wrote {path} and the report in {out}")
    return 0


def write_results(tracker: MindTracker, scenario: str, out: Path, settings: Settings, note: str = "") -> Path:
    """The outputs, and ``settings.toml``: the settings they were made with."""
    path = write_outputs(tracker, scenario, out, note)
    write_text(out / "settings.toml", settings_toml(settings))
    return path


def _serve_arg(parser: argparse.ArgumentParser) -> None:
    """``--serve`` (:func:`serve`)."""
    parser.add_argument(
        "--serve",
        action="store_true",
        help="run one run per line of standard input, each line the JSON list of that run's "
        "options (as on this command line, which gives none of them), with this process's "
        f"imports and caches; each answered on standard output with '{FINISHED} N' once its "
        "outputs, run log and memory are saved, until the input ends (toyroom eval --days)",
    )


def _memory_args(parser: argparse.ArgumentParser) -> None:
    """The run's ``--memory``, ``--checkpoint-ticks`` and ``--keep-days``."""
    parser.add_argument(
        "--memory",
        type=Path,
        metavar="FILE",
        help="the memory of households across days (SQLite; created if missing): a scene that names "
        "its household starts each person from what was learned of them before, and what is "
        "learned is saved (toyroom memory show|forget|export|import); a running brain forgets on "
        "request (toyroom memory forget)",
    )
    parser.add_argument(
        "--checkpoint-ticks",
        type=positive_int,
        default=CHECKPOINT_TICKS,
        metavar="N",
        help=f"save a checkpoint of the memory every N engine ticks of a day (default {CHECKPOINT_TICKS})",
    )
    parser.add_argument(
        "--keep-days",
        type=non_negative_float,
        default=KEEP_DAYS,
        metavar="D",
        help=f"keep D days (of the clock) of the memory's history; older days go at the next save, "
        f"but each household's latest (default {KEEP_DAYS:g})",
    )


def non_negative_float(text: str) -> float:
    """A finite number >= 0 (``--keep-days``, ``--lost-timeout``; argparse names the option)."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number >= 0, not {text!r}") from None
    if not value >= 0 or value == float("inf"):
        raise argparse.ArgumentTypeError(f"expected a number >= 0, not {text!r}")
    return value


def check_settings_parser() -> argparse.ArgumentParser:
    parser = command_parser(
        "python -m brain check-settings",
        "Check the brain's settings and exit: 0 when every value is allowed, 2 with an error naming\n"
        "the setting, its value and what is allowed (`toyroom run` asks before any process starts).",
    )
    add_settings_args(parser)
    add_log_level(parser, "WARNING")
    return parser


def plan_parser() -> argparse.ArgumentParser:
    parser = command_parser(
        "python -m brain plan",
        "Write the planner's Q-values of a scene, for simulated people who act by them.",
    )
    parser.add_argument(
        "--scene", type=Path, required=True, help="the scene as JSON (`python -m sim2d scene`)"
    )
    parser.add_argument("--out", type=Path, required=True, help="the table to write (.npz)")
    add_settings_args(parser)
    add_log_level(parser, "WARNING")
    return parser


def plan_main(scene_path: Path, out: Path, settings: Settings) -> int:
    """Read a scene and write its policy table."""
    try:
        scene = msgspec.json.decode(scene_path.read_bytes(), type=Scene)
    except (OSError, msgspec.ValidationError, msgspec.DecodeError) as err:
        raise BrainError(f"scene {scene_path}: {err}") from err
    check_model_size(scene, settings.model)  # before the planner allocates anything
    print(f"brain: wrote {write_policy_table(out, scene, settings.model)}")
    return 0


def run_live(args: argparse.Namespace, settings: Settings, *, store: bool = True) -> bool:
    """The live node of ``args`` with ``settings`` (its ``--out`` made first, and, with
    ``store``, its ``--values-cache`` used); whether it was stopped (SIGTERM) before the end."""
    episodes = episode_folders(args.episodes) if args.episodes else [(args.scenario, None)]
    if store and args.values_cache is not None:
        use_store(ValueDirectory(args.values_cache))
    if args.out is not None:  # first, so a recorder of this run finds them
        args.out.mkdir(parents=True, exist_ok=True)
        (args.out / "settings.toml").write_text(settings_toml(settings), encoding="utf-8")
    return run_node(args, settings, episodes)


def serve(parser: argparse.ArgumentParser, lines: Iterable[str]) -> int:
    """``--serve``: each of ``lines`` (standard input) the JSON list of one run's options, run
    as :func:`run_live` runs them (one ``--values-cache`` kept while runs name the same), and
    answered with :data:`FINISHED`; until the lines end, or a run is stopped. The exit status.

    Raises:
        BrainError: a line is no list of options, or a run failed (its error).
    """
    cache: Path | None = None
    count = 0
    for line in lines:
        if not line.strip():
            continue
        args = served_args(parser, line)
        logging.getLogger().setLevel(args.log_level)
        settings = load_settings(args.settings, args.overrides)
        if args.values_cache is not None and args.values_cache != cache:
            use_store(ValueDirectory(args.values_cache))
            cache = args.values_cache
        stopped = run_live(args, settings, store=False)
        signal.signal(signal.SIGTERM, signal.SIG_DFL)  # between runs, SIGTERM ends the process
        if stopped:
            break
        count += 1
        print(f"{FINISHED} {count}", flush=True)
    return 0


def served_args(parser: argparse.ArgumentParser, line: str) -> argparse.Namespace:
    """A line of ``--serve``'s input as a run's options.

    Raises:
        BrainError: it is no JSON list of strings, or it asks to serve again.
    """
    try:
        argv = json.loads(line)
    except ValueError as err:
        raise BrainError(f"--serve: a line of input is not JSON ({err}): {line.strip()[:200]}") from None
    if not isinstance(argv, list) or not all(isinstance(a, str) for a in argv):
        raise BrainError(f"--serve: a line of input is not a JSON list of options: {line.strip()[:200]}")
    args = parser.parse_args(argv)
    if args.serve:
        raise BrainError("--serve: a run's options cannot ask to serve again")
    return args


def run_node(
    args: argparse.Namespace, settings: Settings, episodes: Sequence[tuple[str | None, str | None]]
) -> bool:
    """The live node: each of ``episodes`` (a scenario, and its outputs' folder or ``None``:
    the options' folders themselves) in turn, with one session and one node; whether it was
    stopped (SIGTERM) before the end."""
    with (
        Bridge(args.world, settings_from_args(args)) as bridge,
        (
            McapRecorder(
                bridge,
                args.record,
                timeout=args.handshake_timeout,
                settings=lambda: settings_toml(settings),
            )
            if args.record
            else nullcontext()
        ) as recorder,
        (
            open_memory(args.memory, keep_days=args.keep_days) if args.memory is not None else nullcontext()
        ) as store,
    ):
        node = BrainNode(
            bridge,
            settings=settings.model,
            robot_settings=settings.robot,
            observer=Observer(args.observer),
            timeout=args.timeout or None,
            handshake_timeout=args.handshake_timeout or None,
            lost_timeout=args.lost_timeout or None,
            robot=RobotMode(args.robot) if args.robot else None,
            shadows=[Observer(o) for o in args.shadow],
            shadow_dir=args.shadow_out,
            run_log=args.run_log,
            memory=None if store is None else MemoryKeeper(store, args.checkpoint_ticks),
        )
        stop_on_sigterm(node)
        for chosen, folder in episodes:
            if folder is not None:
                node.shadow_dir = args.shadow_out / folder
                node.run_log = args.run_log / folder if args.run_log is not None else None
            try:
                scenario, tracker = node.run(chosen, args.seed, max_ticks=args.max_ticks)
            except (BrainError, BridgeError, ProtocolError) as err:
                if folder is None:
                    raise
                raise BrainError(f"episode of {chosen}: {err}") from err
            last = tracker.ticks[-1] if tracker.ticks else "none"
            note = STOPPED_NOTE.format(tick=last) if node.stopped else ""
            if args.out is not None:
                out = args.out / folder if folder is not None else args.out
                path = write_results(tracker, scenario, out, settings, note)
                print(f"brain: wrote {path} and the report in {out}", flush=True)
            if node.stopped:
                print(f"brain: {note}", flush=True)
                break
    if recorder is not None and recorder.error is not None:  # a full disk: the rest is lost
        raise BrainError(f"--record: {recorder.error}")
    return node.stopped


STOPPED_NOTE = (
    "stopped (SIGTERM) at tick {tick}, before the episode's end: the outputs cover the ticks until then"
)


def stop_on_sigterm(node: BrainNode) -> None:
    """On SIGTERM, end the episode at the next tick and write what the brain has (the caller
    of :meth:`BrainNode.run` sees :attr:`BrainNode.stopped`): a brain stopped early, as
    ``toyroom play`` stops one at a study's goal, keeps its outputs. Main thread only."""
    signal.signal(signal.SIGTERM, lambda *_: node.stopping.set())


def episode_folders(scenarios: Sequence[str]) -> list[tuple[str, str]]:
    """Each scenario of ``--episodes`` and the folder its outputs go to (its file's stem).

    Raises:
        BrainError: two scenarios would share a folder.
    """
    folders: dict[str, str] = {}
    for scenario in scenarios:
        stem = Path(scenario).stem
        if stem in folders.values():  # the same scenario twice, or two files of one name
            raise BrainError(f"--episodes: two scenarios named '{stem}' would share their outputs' folder")
        folders[scenario] = stem
    return list(folders.items())


SUBCOMMANDS = {
    "memory": memory_parser,
    "infer": infer_parser,
    "plan": plan_parser,
    "check-settings": check_settings_parser,
}


def main(argv: Sequence[str] | None = None) -> int:
    """Run the brain node (or its ``memory``, ``infer``, ``plan`` or ``check-settings``
    subcommand) on ``argv``; the exit status."""
    argv = list(sys.argv[1:] if argv is None else argv)
    sub = argv[0] if argv and argv[0] in SUBCOMMANDS else None
    parser = SUBCOMMANDS.get(sub or "", run_parser)()
    args = parser.parse_args(argv[1:] if sub else argv)
    configure_logging(args.log_level)
    if getattr(args, "world", None) is not None and (problem := world_problem(args.world)) is not None:
        print(f"brain: {problem}", file=sys.stderr)
        return 2
    if sub == "memory":  # its errors named as the user called it (toyroom memory)
        try:
            return memory_main(args)
        except BrainError as err:
            print(f"{parser.prog}: {err}", file=sys.stderr)
            return 2
    try:
        settings = load_settings(args.settings, args.overrides)
        if sub == "check-settings":
            return 0
        if sub == "plan":
            return plan_main(args.scene, args.out, settings)
        if sub == "infer":
            return infer_main(args.trace, args.out, Observer(args.observer), settings, args.note)
        if args.print_tree:
            print(RobotTree("robot", (0, 0)).render())
            return 0
        exit_with_parent()  # started by toyroom run or eval: not to outlive it
        if args.serve:
            return serve(parser, iter(sys.stdin.readline, ""))
        run_live(args, settings)
        return 0
    except (BrainError, BridgeError, ProtocolError) as err:
        print(f"brain: {err}", file=sys.stderr)
        return 2
    except OutputError as err:  # a full disk writing the outputs: one line, none half written
        print(f"brain: {err}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())


__all__ = ["MindTracker", "main"]
