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
import threading
import time
from contextlib import nullcontext
from dataclasses import dataclass
from pathlib import Path

from rich.console import Console
from rich.live import Live

from protocol import Mind, Observer

from ..bridge import Bridge
from ..errors import BridgeError
from ..flags import settings_argv
from ..processes import (
    engine_command,
    node_command,
    report_failure,
    start_gateway,
    start_node,
    stop_node,
    wait_for_engine,
)
from ..pubsub import Received
from ..recording.events import write_events_csv
from ..recording.mcap import McapRecorder
from ..recording.trace import TraceRecorder
from ..session import SessionSettings
from .livetable import mind_table

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
    """``sim2d`` (the pymunk engine), ``grid`` (the example grid engine) or ``csharp`` (the C#
    SDK's grid engine under Mono, always through the gateway)."""
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
    config.out.mkdir(parents=True, exist_ok=True)
    through = config.gateway or config.engine == "csharp"  # the C# engine has no Zenoh
    gateway, url = start_gateway(world, settings, config.out / "gateway.log") if through else (None, None)
    try:
        if config.engine == "csharp":
            from ..gateway import csharp

            scenarios = config.out / "scenarios"
            csharp.export_scenario(config.scenario, scenarios)
            command = csharp.engine_command(url or "", scenarios, *engine_args)
        else:
            command = engine_command(config.engine, world, settings, *engine_args, gateway=url)
    except BridgeError:
        if gateway is not None:
            stop_node(gateway)
        raise
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
            settings_file = config.out / "settings.toml"
            mcap = (
                McapRecorder(bridge, config.record, info=info, settings=lambda: _read(settings_file))
                if config.record
                else nullcontext()
            )
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
                    *settings_argv(config.settings, config.overrides),
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
        for process in (brain, engine, viewer, gateway):
            if process is not None:
                stop_node(process)


def _read(path: Path) -> str | None:
    """A file's text, or ``None`` when it is not there (yet)."""
    try:
        return path.read_text(encoding="utf-8")
    except OSError:
        return None
