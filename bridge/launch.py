"""``toyroom run``: the engine and the brain, each its own process, on a private loopback
world in lock-step, with every message recorded to ``DIR/trace.jsonl``.

The bridge starts the nodes as ``python -m sim2d`` and ``python -m brain`` (it never
imports them), waits for the brain to finish the episode, then stops the engine. The run
fails (non-zero exit) when either node fails.
"""

from __future__ import annotations

import logging
import os
import subprocess
import sys
import time
from dataclasses import dataclass
from pathlib import Path

from .node import Bridge
from .recorder import TraceRecorder
from .session import SessionSettings

log = logging.getLogger("toyroom.run")


@dataclass(frozen=True)
class RunConfig:
    """What ``toyroom run`` runs. ``world`` defaults to a name of this process alone."""

    scenario: str
    out: Path
    seed: int = 0
    observer: str = "btom"
    world: str | None = None
    timeout: float = 10.0
    log_level: str = "WARNING"


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


def node_command(package: str, world: str, settings: SessionSettings, *args: str) -> list[str]:
    """The command line of a node process."""
    return [sys.executable, "-m", package, "--world", world, *_network_args(settings), *args]


def run(config: RunConfig, settings: SessionSettings | None = None) -> int:
    """Run one episode; return the exit status (0 when both nodes did their job)."""
    settings = settings or SessionSettings()
    world = config.world or f"run-{os.getpid()}"
    config.out.mkdir(parents=True, exist_ok=True)
    engine = subprocess.Popen(
        node_command(
            "sim2d",
            world,
            settings,
            "--scenario",
            config.scenario,
            "--lockstep",
            "--log-level",
            config.log_level,
        )
    )
    brain: subprocess.Popen[bytes] | None = None
    try:
        with Bridge(world, settings) as bridge, TraceRecorder(bridge, config.out / "trace.jsonl"):
            brain = subprocess.Popen(
                node_command(
                    "brain",
                    world,
                    settings,
                    "--scenario",
                    config.scenario,
                    "--seed",
                    str(config.seed),
                    "--out",
                    str(config.out),
                    "--observer",
                    config.observer,
                    "--timeout",
                    str(config.timeout),
                    "--log-level",
                    config.log_level,
                )
            )
            while brain.poll() is None:
                if engine.poll() is not None:
                    log.error("the engine exited with status %s before the episode ended", engine.returncode)
                    brain.terminate()
                    brain.wait(timeout=10)
                    return engine.returncode or 1
                time.sleep(0.1)
            time.sleep(0.2)  # let the last messages reach the recorder
        if brain.returncode != 0:
            log.error("the brain exited with status %s", brain.returncode)
        return brain.returncode
    finally:
        for process in (brain, engine):
            if process is not None and process.poll() is None:
                process.terminate()
                try:
                    process.wait(timeout=10)
                except subprocess.TimeoutExpired:
                    process.kill()
