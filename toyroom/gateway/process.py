"""The gateway as a process: its command line (``python -m toyroom.gateway``), and starting one
on a free loopback port, its URL read from the line it prints once it listens."""

from __future__ import annotations

import re
import subprocess
import sys
import threading
import time
from pathlib import Path

from bridge.errors import BridgeError
from bridge.processes import network_args, start_node, stop_node, stop_nodes
from bridge.session import SessionSettings

GATEWAY_READY = re.compile(r"toyroom gateway: world '[^']*' on (?P<url>ws://[^\s()]+) \(ready\)")
"""The line the gateway prints once it listens (:func:`toyroom.gateway.node.main`); ``url``:
where."""


def gateway_command(world: str, settings: SessionSettings, listen: str) -> list[str]:
    """The command line of ``python -m toyroom.gateway`` serving ``world`` on ``listen``."""
    zenoh = network_args(settings)
    zenoh = ["--zenoh-listen" if arg == "--listen" else arg for arg in zenoh]
    return [
        sys.executable,
        "-X",
        "faulthandler",
        "-m",
        "toyroom.gateway",
        "--world",
        world,
        "--listen",
        listen,
        *zenoh,
    ]


def start_gateway(
    world: str,
    settings: SessionSettings,
    log_path: Path,
    timeout: float = 30.0,
    *,
    group: bool = False,
    stop: threading.Event | None = None,
) -> tuple[subprocess.Popen[bytes], str]:
    """A gateway process on a free loopback port, and its URL once it listens (``group``: see
    :func:`bridge.processes.start_node`).

    Raises:
        BridgeError: it exited, or did not say it listens within ``timeout`` s (its log says
            why), or ``stop`` was set first.
    """
    process = start_node(gateway_command(world, settings, "ws://127.0.0.1:0"), log_path, group=group)
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline and not (stop is not None and stop.is_set()):
        match = GATEWAY_READY.search(log_path.read_text(encoding="utf-8", errors="replace"))
        if match:
            return process, match.group("url")
        if process.poll() is not None:
            break
        time.sleep(0.05)
    if group:
        stop_nodes([process])
    else:
        stop_node(process)
    raise BridgeError(f"the gateway did not start (exit status {process.returncode}); see {log_path}")
