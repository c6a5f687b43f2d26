"""``toyroom run``: the engine and the brain, each its own process, on a private loopback
world in lock-step, with every message recorded to ``DIR/trace.jsonl`` and every discrete
event listed in ``DIR/events.csv``; a live table shows what the brain infers and what the
robot does.

The bridge starts the nodes as ``python -m sim2d`` and ``python -m brain`` (it never
imports them), waits for the brain to finish the episode, then stops the engine. The run
fails (non-zero exit) when either node fails.
"""

from __future__ import annotations

import logging
import os
import subprocess
import sys
import threading
import time
from contextlib import nullcontext
from dataclasses import dataclass
from pathlib import Path

from rich.console import Console
from rich.live import Live

from protocol import EngineInfo, Mind, Observer

from .errors import BridgeError, NoReply
from .eventlog import write_events_csv
from .handshake import handshake
from .livetable import mind_table
from .mcaprec import McapRecorder
from .node import Bridge
from .recorder import TraceRecorder
from .session import SessionSettings
from .typed import Received

log = logging.getLogger("toyroom.run")


@dataclass(frozen=True)
class RunConfig:
    """What ``toyroom run`` runs. ``world`` defaults to a name of this process alone."""

    scenario: str
    out: Path
    seed: int = 0
    observer: str = Observer.BTOM.value
    world: str | None = None
    timeout: float = 10.0
    log_level: str = "WARNING"
    robot: str | None = None
    """``act`` or ``observe`` to override the scenario's robot mode."""
    engine: str = "sim2d"
    """``sim2d`` (the pymunk engine) or ``grid`` (the example grid engine)."""
    live: bool | None = None
    """Show the live table (default: when standard output is a terminal)."""
    record: Path | None = None
    """Also record every message to this MCAP file."""
    view: bool = False
    """Also start the meshcat viewer (its URL is printed; it closes with the run)."""
    shadows: tuple[str, ...] = ()
    """Observers the brain also runs on the same ticks, their minds in ``out/minds-<name>.jsonl``."""


def _network_args(settings: SessionSettings) -> list[str]:
    args: list[str] = []
    if settings.config_file is not None:
        args += ["--zenoh-config", str(settings.config_file)]
    if settings.mode is not None:
        args += ["--mode", settings.mode]
    for endpoint in settings.listen or ():
        args += ["--listen", endpoint]
    for endpoint in settings.connect or ():
        args += ["--connect", endpoint]
    return args


CHECKOUT = Path(__file__).resolve().parents[1]
"""The source checkout this package runs from (when it does: an installed wheel has no
``bench/`` or ``examples/`` beside it)."""


def source_file(relative: str, what: str = "") -> Path:
    """``relative`` in the source checkout, or a :class:`BridgeError` saying in one line that
    ``what`` (the command, when empty) needs a source checkout."""
    path = CHECKOUT / relative
    if not path.is_file():
        raise BridgeError(
            f"{what + ' ' if what else ''}needs a source checkout: {relative} is not part of the "
            "installed package (clone the repository and run it there)"
        )
    return path


GRID_ENGINE = "examples/grid_engine/main.py"
"""The example engine written from the protocol documents alone (plain zenoh and json)."""


def node_command(package: str, world: str, settings: SessionSettings, *args: str) -> list[str]:
    """The command line of a node process (with Python's fault handler on, so a crash in
    native code leaves every thread's Python stack in the node's log)."""
    return [
        sys.executable,
        "-X",
        "faulthandler",
        "-m",
        package,
        "--world",
        world,
        *_network_args(settings),
        *args,
    ]


def engine_command(engine: str, world: str, settings: SessionSettings, *args: str) -> list[str]:
    """The command line of an engine: ``sim2d``, or ``grid`` (default loopback network only)."""
    if engine == "grid":
        return [sys.executable, str(source_file(GRID_ENGINE, "--engine grid")), "--world", world, *args]
    return node_command("sim2d", world, settings, *args)


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
    """Run one episode; return the exit status (0 when both nodes did their job)."""
    settings = settings or SessionSettings()
    world = config.world or f"run-{os.getpid()}"
    robot = ["--robot", config.robot] if config.robot else []
    engine_args = ["--scenario", config.scenario, "--lockstep", "--log-level", config.log_level, *robot]
    command = engine_command(config.engine, world, settings, *engine_args)
    config.out.mkdir(parents=True, exist_ok=True)
    engine_log, brain_log = config.out / "engine.log", config.out / "brain.log"
    engine = start_node(command, engine_log)
    brain: subprocess.Popen[bytes] | None = None
    viewer = None
    if config.view:
        viewer = start_node(node_command("bridge.view", world, settings), config.out / "viewer.log")
        print(f"toyroom run: the viewer's URL is in {config.out / 'viewer.log'}")
    try:
        with Bridge(world, settings) as bridge:
            info = wait_for_engine(bridge, engine)
            if info is None:
                report_failure("engine", engine.returncode, engine_log)
                return engine.returncode or 1
            view = MindView(f"toyroom run: {config.scenario} (world {world})", config.live)
            mcap = McapRecorder(bridge, config.record, info=info) if config.record else nullcontext()
            with TraceRecorder(bridge, config.out / "trace.jsonl", info=info), mcap, view:
                bridge.subscribe(bridge.keys.mind, view.on_mind, expected=Mind)
                brain_args = [
                    *("--scenario", config.scenario, "--seed", str(config.seed), "--out", str(config.out)),
                    *(
                        "--observer",
                        config.observer,
                        "--timeout",
                        str(config.timeout),
                        "--log-level",
                        config.log_level,
                    ),
                    *robot,
                    *(arg for name in config.shadows for arg in ("--shadow", name)),
                    *(("--shadow-out", str(config.out)) if config.shadows else ()),
                ]
                brain = start_node(node_command("brain", world, settings, *brain_args), brain_log)
                while brain.poll() is None:
                    if engine.poll() is not None:
                        log.error(
                            "the engine exited with status %s before the episode ended", engine.returncode
                        )
                        return engine.returncode or 1
                    view.refresh(0.1)
                time.sleep(0.2)  # let the last messages reach the recorder
        rows = write_events_csv(config.out / "trace.jsonl", config.out / "events.csv")
        print(
            f"toyroom run: results in {config.out}/ (mind.csv, events.csv with {rows} rows, report.md, ...)"
        )
        if brain.returncode != 0:
            report_failure("brain", brain.returncode, brain_log)
        return brain.returncode
    finally:
        for process in (brain, engine, viewer):
            if process is not None:
                stop_node(process)


def start_node(command: list[str], log_path: Path) -> subprocess.Popen[bytes]:
    """Start a node with its output going to ``log_path`` (kept with the results)."""
    with log_path.open("wb") as handle:
        return subprocess.Popen(command, stdout=handle, stderr=subprocess.STDOUT)


def stop_node(process: subprocess.Popen[bytes], grace: float = 10.0) -> None:
    """SIGTERM, then SIGKILL if it has not exited within ``grace`` seconds."""
    if process.poll() is not None:
        return
    process.terminate()
    try:
        process.wait(timeout=grace)
    except subprocess.TimeoutExpired:
        log.warning("process %d ignored SIGTERM for %g s: killed", process.pid, grace)
        process.kill()
        process.wait(timeout=grace)


def report_failure(node: str, status: int | None, log_path: Path, lines: int = 20) -> None:
    """Say that a node failed, with the end of its log."""
    tail = (
        log_path.read_text(encoding="utf-8", errors="replace").splitlines()[-lines:]
        if log_path.exists()
        else []
    )
    print(f"toyroom run: the {node} exited with status {status}; end of {log_path}:", file=sys.stderr)
    for line in tail:
        print(f"  {line}", file=sys.stderr)


def wait_for_engine(
    bridge: Bridge, engine: subprocess.Popen[bytes], timeout: float = 60.0
) -> EngineInfo | None:
    """The engine's handshake, or ``None`` when its process exits first."""
    deadline = time.monotonic() + timeout
    while engine.poll() is None:
        try:
            return handshake(bridge, client="toyroom-run", role="recorder", timeout=0.5)
        except NoReply:
            if time.monotonic() > deadline:
                raise
    return None
