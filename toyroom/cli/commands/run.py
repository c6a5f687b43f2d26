"""``toyroom run``: the engine and the brain, each its own process, on a private loopback
world in lock-step, with every message recorded to ``DIR/trace.jsonl`` and every discrete
event listed in ``DIR/events.csv``; a live table shows what the brain infers and what the
robot does.

The bridge starts the nodes as ``python -m sim2d`` and ``python -m brain`` (it never
imports them), each the leader of a process group of its own, waits for the brain to finish
the episode, then stops the engine. Before any of it, the brain checks the settings
(``python -m brain check-settings``). The outputs go to a fresh folder that takes the place of
``DIR`` only when the run finished (:mod:`toyroom.cli.outfolder`); a run that fails (a node failed: exit
1) or is stopped (SIGINT, SIGTERM, SIGHUP: :mod:`toyroom.cli.stopping`, exit ``128 + N``) stops every
node, writes what can be written and leaves a ``FAILED`` note (:mod:`toyroom.cli.outcome`).
"""

from __future__ import annotations

import argparse
import logging
import os
import subprocess
import sys
import threading
from contextlib import nullcontext
from dataclasses import dataclass, field, replace
from pathlib import Path

from rich.console import Console
from rich.live import Live

from bridge.bridge import Bridge
from bridge.errors import BridgeError
from bridge.flags import add_settings_args, out_file_problem, settings_argv
from bridge.processes import (
    check_brain_settings,
    engine_command,
    node_command,
    report_failure,
    start_node,
    stop_nodes,
    wait_for_engine,
)
from bridge.pubsub import Received
from bridge.recording.mcap import McapRecorder
from bridge.recording.trace import TraceRecorder
from bridge.session import SessionSettings, add_network_args, settings_from_args
from protocol import EngineInfo, Mind, Observer, RobotMode, State
from protocol import Error as ProtocolErrorBase

from ...gateway import start_gateway
from ..floors import timeout_problem
from ..livetable import mind_table
from ..options import observer_option
from ..outcome import (
    RunOutcome,
    discard_brain_outputs,
    events_csv,
    exit_text,
    failure_note,
    infer_argv,
    infer_from_trace,
    not_one_episode,
    running_note,
    trace_span,
)
from ..outfolder import FAILED, RunFolder
from ..scenariocheck import scenario_checked
from ..stopping import Interrupted, StopRequest, signal_name
from ..subcommand import Subcommand

log = logging.getLogger("toyroom.run")

RUN_LEASE_MS = 8000
"""The lease of ``toyroom run``'s nodes (ms): a node stalled (SIGSTOP, a loaded machine) for up
to 8 s keeps its links, so the episode simply waits for it; it is below the brain's 10 s step
timeout, so an engine stalled for longer is taken for gone (and the brain carries on or stops,
saying why) before the step times out. A killed node closes its links and is noticed at once."""
GATEWAY_ONLY = ("csharp", "godot")
"""Engines without Zenoh: ``toyroom run`` starts a gateway for them and exports the scenario."""
NOT_ONE_EPISODE = "removed: they are not one episode's; toyroom infer makes them of the trace's last episode"
"""Why a run whose trace is not one episode's ticks keeps no brain outputs (its ``FAILED`` note)."""


@dataclass(frozen=True)
class RunConfig:
    """What ``toyroom run`` runs. ``world`` defaults to a name of this process alone."""

    scenario: str
    out: Path
    seed: int = 0
    observer: Observer = Observer.BTOM
    world: str | None = None
    timeout: float = 10.0
    log_level: str = "WARNING"
    robot: RobotMode | None = None
    """``act`` or ``observe`` to override the scenario's robot mode."""
    engine: str = "sim2d"
    """``sim2d`` (the pymunk engine), ``grid`` (the example grid engine), ``csharp`` (the C#
    SDK's grid engine under Mono) or ``godot`` (the Godot add-on's sample under
    ``godot3-server``); the last two always through the gateway."""
    gateway: bool = False
    """Start ``toyroom gateway`` and connect the engine through it (a WebSocket, no Zenoh)."""
    live: bool | None = None
    """Show the live table (default: when standard output is a terminal)."""
    record: Path | None = None
    """Also record every message to this MCAP file."""
    view: bool = False
    """Also start the meshcat viewer (its URL is printed; it closes with the run)."""
    shadows: tuple[str, ...] = ()
    """Observers the brain also runs on the same ticks, their minds in ``out/minds-<name>.jsonl``."""
    settings: Path | None = None
    """A settings file for the brain (``[model]``, ``[robot]``)."""
    overrides: tuple[str, ...] = ()
    """``NAME=VALUE`` settings for the brain, after the file's."""
    lease_ms: int = RUN_LEASE_MS
    """How long, in milliseconds, the engine's and the brain's links outlive a stall of either
    (their sessions' lease): a stall shorter than this is waited for and the episode runs on."""
    memory: Path | None = None
    """The brain's memory of households (``--memory``): a scenario that names its household
    starts from it, and its day is saved there."""


class MindView:
    """The live table of the latest ``mind`` message (or just the last one, printed at the end,
    when the output is not a terminal)."""

    def __init__(self, title: str, live: bool | None) -> None:
        self.title = title
        self.console = Console()
        self.live = self.console.is_terminal if live is None else live
        self.latest: Mind | None = None
        self.changed = threading.Event()
        self._display: Live | None = None

    def on_mind(self, mind: Mind, _: Received) -> None:
        self.latest = mind
        self.changed.set()

    def __enter__(self) -> MindView:
        if self.live:
            self._display = Live(mind_table(None, self.title), console=self.console, refresh_per_second=4)
            self._display.__enter__()
        return self

    def refresh(self, wait: float) -> None:
        """Wait up to ``wait`` seconds for news and redraw."""
        if self.changed.wait(wait):
            self.changed.clear()
            if self._display is not None:
                self._display.update(mind_table(self.latest, self.title))

    def __exit__(self, *exc: object) -> None:
        if self._display is not None:
            self._display.update(mind_table(self.latest, self.title))
            self._display.__exit__(None, None, None)
        elif self.latest is not None:
            self.console.print(mind_table(self.latest, self.title))


def run(config: RunConfig, settings: SessionSettings | None = None) -> int:
    """Run one episode into a fresh folder that takes the place of ``config.out`` when done
    (:mod:`toyroom.cli.outfolder`); a run that does not finish leaves its outputs marked ``FAILED``.

    Returns:
        0 when both nodes did their job, 1 when a node failed, ``128 + N`` when signal N
        (SIGINT, SIGTERM, SIGHUP) stopped it.

    Raises:
        BridgeError: before any node starts: ``--out`` names a file or another project's
            folder, the scenario or a setting is not allowed, the engine cannot be run here.
    """
    settings = replace(settings or SessionSettings(), lease_ms=config.lease_ms)
    world = config.world or f"run-{os.getpid()}"
    folder = RunFolder(config.out)
    if config.engine not in GATEWAY_ONLY:  # their command is made once the scenario is exported
        engine_command(config.engine, world, settings, gateway="ws://127.0.0.1:0" if config.gateway else None)
    elif config.engine == "godot":
        from ...gateway import godot

        godot.godot()  # installed, and a source checkout to run
    with scenario_checked(config.scenario):  # both before any node starts
        check_brain_settings(config.settings, config.overrides)
    with StopRequest() as stop:
        observer = config.observer.value
        staging = folder.open(lambda out: running_note(os.getpid(), infer_argv(out, observer, [])))
        try:
            outcome = Episode(config, settings, world, staging, stop).run()
            return _conclude(config, folder, outcome, stop)
        except OSError as err:
            why = f"{outcome.reason}, and " if outcome.reason else ""
            print(
                f"toyroom run: {why}cannot put the outputs in place ({err}); they are in {staging}/",
                file=sys.stderr,
            )
            return 1
        finally:
            folder.release()


@dataclass
class Episode:
    """One episode's nodes, their outputs in ``out``: started, followed, and all stopped."""

    config: RunConfig
    settings: SessionSettings
    world: str
    out: Path
    stop: StopRequest
    nodes: list[subprocess.Popen[bytes]] = field(default_factory=list)

    def run(self) -> RunOutcome:
        """Run the episode; how it ended. Every node started is stopped (its whole process
        group) before this returns."""
        try:
            return self._start()
        except Interrupted as err:
            return RunOutcome(128 + err.signum, str(err))
        except (BridgeError, ProtocolErrorBase) as err:
            if self.stop.signum is not None:
                return RunOutcome(self.stop.exit_status, f"interrupted by {signal_name(self.stop.signum)}")
            return RunOutcome(1, str(err))
        except Exception as err:  # a bug here: say so, and still stop the nodes and mark the folder
            log.exception("toyroom run failed")
            return RunOutcome(1, f"toyroom run's own error ({err!r})")
        finally:
            stop_nodes(list(reversed(self.nodes)))

    def _node(self, command: list[str], log: str) -> subprocess.Popen[bytes]:
        """Start a node (a process group of its own), its output in ``out/log``."""
        self.nodes.append(start_node(command, self.out / log, group=True))
        return self.nodes[-1]

    def _engine_command(self, url: str | None) -> list[str]:
        """The engine's command line (the C# engine's after exporting the scenario for it)."""
        config = self.config
        robot = ["--robot", config.robot] if config.robot else []
        args = ["--scenario", config.scenario, "--lockstep", "--log-level", config.log_level, *robot]
        if config.engine not in GATEWAY_ONLY:
            return engine_command(config.engine, self.world, self.settings, *args, gateway=url)
        from ...gateway import csharp, godot

        csharp.export_scenario(config.scenario, self.out / "scenarios")
        client = godot if config.engine == "godot" else csharp
        return client.engine_command(url or "", self.out / "scenarios", *args)

    def _start(self) -> RunOutcome:
        """Start the gateway (when the engine needs one), the engine and the viewer, wait for
        the engine's handshake, then :meth:`_follow`."""
        url = None
        if self.config.gateway or self.config.engine in GATEWAY_ONLY:  # no Zenoh in those engines
            log = self.out / "gateway.log"
            gateway, url = start_gateway(self.world, self.settings, log, group=True, stop=self.stop.event)
            self.nodes.append(gateway)
        command = self._engine_command(url)
        self.stop.check()
        engine = self._node(command, "engine.log")
        if self.config.view:
            self._node(node_command("toyroom.view", self.world, self.settings), "viewer.log")
            print(f"toyroom run: the viewer's URL is in {self.out / 'viewer.log'}")
        with Bridge(self.world, self.settings) as bridge:
            info = wait_for_engine(bridge, engine, stop=self.stop.event)
            self.stop.check()
            if info is None:
                reason = f"the engine {exit_text(engine.returncode)} before it answered the handshake"
                return RunOutcome(1, reason, node=("engine", engine.returncode))
            return self._follow(bridge, info, engine)

    def _follow(self, bridge: Bridge, info: EngineInfo, engine: subprocess.Popen[bytes]) -> RunOutcome:
        """Record the world and show the minds while the brain runs the episode."""
        config, out = self.config, self.out
        view = MindView(f"toyroom run: {config.scenario} (world {self.world})", config.live)
        settings_file = out / "settings.toml"
        mcap = (
            McapRecorder(bridge, config.record, info=info, settings=lambda: _read(settings_file))
            if config.record
            else nullcontext()
        )
        ended = threading.Event()  # the latest state says the episode is over

        def on_state(state: State, _: Received) -> None:
            if state.done:
                ended.set()
            else:
                ended.clear()

        trace = TraceRecorder(bridge, out / "trace.jsonl", info=info)
        with trace, mcap, view:
            bridge.subscribe(bridge.keys.mind, view.on_mind, expected=Mind)
            bridge.subscribe(bridge.keys.state, on_state, expected=State)
            brain_args = _brain_args(config, out)
            brain = self._node(node_command("brain", self.world, self.settings, *brain_args), "brain.log")
            while brain.poll() is None:
                self.stop.check()
                if (error := _write_error(trace, mcap)) is not None:  # a full disk: nothing can be kept
                    return RunOutcome(1, error)
                # after the last state the brain needs the engine no more: it finishes alone
                if engine.poll() is not None and not ended.wait(0.5):
                    reason = f"the engine {exit_text(engine.returncode)} before the episode ended"
                    return RunOutcome(1, reason, infer=True, node=("engine", engine.returncode))
                view.refresh(0.1)
            self.stop.event.wait(0.2)  # let the last messages reach the recorder
        if (error := _write_error(trace, mcap)) is not None:
            return RunOutcome(1, error)
        if brain.returncode != 0:
            reason = f"the brain {exit_text(brain.returncode)}{_last_line(out / 'brain.log')}"
            return RunOutcome(1, reason, node=("brain", brain.returncode))
        problem = not_one_episode(out / "trace.jsonl")  # what no node may pass off as one run
        if problem is not None:
            return RunOutcome(1, problem, removed=NOT_ONE_EPISODE)
        if engine.poll() not in (None, 0):
            print(
                f"toyroom run: the engine {exit_text(engine.returncode)} after the episode ended",
                file=sys.stderr,
            )
        return RunOutcome(0)


def _write_error(*recorders: object) -> str | None:
    """Why one of the run's recordings stopped being written (a full disk), or ``None``."""
    for recorder in recorders:
        error = getattr(recorder, "error", None)  # a recorder (nullcontext when not recording)
        if error is not None:
            return str(error)
    return None


def _brain_args(config: RunConfig, out: Path) -> list[str]:
    """The brain's command-line options for this run, its outputs in ``out``."""
    return [
        *("--scenario", config.scenario, "--seed", str(config.seed), "--out", str(out)),
        *("--observer", config.observer.value, "--timeout", str(config.timeout)),
        *("--log-level", config.log_level),
        *(["--robot", config.robot] if config.robot else []),
        *(arg for name in config.shadows for arg in ("--shadow", name)),
        *(("--shadow-out", str(out)) if config.shadows else ()),
        *settings_argv(config.settings, config.overrides),
        *(("--memory", str(config.memory.resolve())) if config.memory is not None else ()),
    ]


def _conclude(config: RunConfig, folder: RunFolder, outcome: RunOutcome, stop: StopRequest) -> int:
    """Write what can still be written (``events.csv``; for a failed engine, the brain's
    outputs inferred from the trace), mark a run that did not finish ``FAILED``, and move the
    folder into place; the exit status."""
    out = folder.staging
    rows = events_csv(out)
    if outcome.status == 0:
        folder.finish()
        print(
            f"toyroom run: results in {config.out}/ (mind.csv, events.csv with {rows} rows, report.md, ...)"
        )
        return 0
    discard_brain_outputs(out)  # the brain was stopped, or failed: they may be half written
    destination = folder.failed_destination()
    span = trace_span(out / "trace.jsonl")
    recorded = (out / "settings.toml").is_file()  # toyroom infer reads it beside the trace
    options = [] if recorded else settings_argv(config.settings, config.overrides)
    reason, inferred = outcome.reason, None
    if outcome.infer and span is not None and stop.signum is None:
        inferred = infer_from_trace(out, infer_argv(out, config.observer.value, options), stop.event)
        if inferred is None and stop.signum is not None:
            reason += (
                f" (and inferring the minds from the trace was interrupted by {signal_name(stop.signum)})"
            )
    argv = infer_argv(destination, config.observer.value, options)
    note = failure_note(reason, out, span, argv, inferred, outcome.removed)
    (out / FAILED).write_text(note, encoding="utf-8")
    placed = folder.place_failed(destination)
    if outcome.node is not None:
        report_failure(outcome.node[0], outcome.node[1], placed / f"{outcome.node[0]}.log")
    print(f"toyroom run: {reason}; partial outputs in {placed}/, see {placed / FAILED}", file=sys.stderr)
    return outcome.status


def _last_line(log_path: Path) -> str:
    """``: `` and the last line of a log, or nothing when it is empty or missing."""
    lines = _read(log_path)
    last = [line for line in (lines or "").splitlines() if line.strip()][-1:]
    return f": {last[0].strip()}" if last else ""


def _read(path: Path) -> str | None:
    """A file's text, or ``None`` when it is not there (yet)."""
    try:
        return path.read_text(encoding="utf-8")
    except OSError:
        return None


def options(parser: argparse.ArgumentParser) -> None:
    """``toyroom run``'s options."""
    parser.add_argument("--scenario", default="paper-robot", help="bundled scenario name or .toml path")
    parser.add_argument("--out", type=Path, default=Path("out"), help="results directory")
    parser.add_argument("--seed", type=int, default=0, help="episode seed (the engine's random draws)")
    observer_option(parser, "the brain's person model")
    add_settings_args(parser)
    parser.add_argument(
        "--shadow",
        choices=Observer.names(),
        action="append",
        default=[],
        help="also run this observer on the same ticks, its minds in OUT/minds-NAME.jsonl (repeatable)",
    )
    parser.add_argument(
        "--timeout", type=float, default=10.0, help="seconds per lock-step request (0: none; else >= 1)"
    )
    parser.add_argument(
        "--robot", choices=RobotMode.names(), help="override whether the robot acts (default: the scene's)"
    )
    parser.add_argument(
        "--engine",
        choices=("sim2d", "grid", "csharp", "godot"),
        default="sim2d",
        help="sim2d (pymunk), grid (examples/grid_engine/), csharp (the C# SDK's grid engine under "
        "Mono, through the gateway; needs mono-devel) or godot (the Godot add-on's sample under "
        "godot3-server, through the gateway); grid, csharp and godot need a source checkout",
    )
    parser.add_argument(
        "--gateway",
        action="store_true",
        help="start `toyroom gateway` and connect the engine through it (a WebSocket instead of Zenoh; grid)",
    )
    parser.add_argument("--no-live", action="store_true", help="no live table (only the final one)")
    parser.add_argument("--record", type=Path, metavar="FILE.mcap", help="also record every message to MCAP")
    parser.add_argument("--view", action="store_true", help="also open the meshcat live view")
    parser.add_argument("--memory", type=Path, metavar="FILE", help="the brain's memory, as brain --memory")
    add_network_args(parser)
    parser.set_defaults(world=None)


def problem(args: argparse.Namespace) -> str | None:
    """``--record`` names a folder or a file in a missing one, or ``--timeout`` is below its floor
    (:mod:`toyroom.cli.floors`), in one line; else ``None``."""
    if args.record is not None:
        if (found := out_file_problem(args.record, "--record", make_folder=False)) is not None:
            return found
    return timeout_problem(args.timeout, none=True)


def handle(args: argparse.Namespace) -> int:
    """``toyroom run``: :func:`run` with the parsed options as a :class:`RunConfig`."""
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


COMMAND = Subcommand(
    "run",
    "run an engine and the brain together, in lock-step, and keep the results",
    options,
    handle,
    problem,
    out_folder=True,
)
