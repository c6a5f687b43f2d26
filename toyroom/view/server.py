"""The meshcat server of ``toyroom view``, on loopback only (``python -m toyroom.view.server``).

meshcat's own server (``python -m meshcat.servers.zmqserver``) binds its ZMQ socket to
127.0.0.1 but its web server to every interface (tornado's default), so another machine
could watch the world although the printed URL says 127.0.0.1. This is the same server
(meshcat's :class:`~meshcat.servers.zmqserver.ZMQWebSocketBridge`) with the web server on
127.0.0.1 too; :func:`start_server` starts it as a process of its own group and returns its
ZMQ URL, for a ``meshcat.Visualizer(zmq_url=...)``.
"""

from __future__ import annotations

import functools
import subprocess
import sys
import tempfile
from typing import Any

from meshcat.servers.zmqserver import ZMQWebSocketBridge

from bridge.processes import exit_with_parent, node_environment

LOOPBACK = "127.0.0.1"
SERVER_MODULE = "toyroom.view.server"
"""The module the server process runs (what its command line names)."""


class LoopbackBridge(ZMQWebSocketBridge):
    """meshcat's ZMQ-to-WebSocket server, its ZMQ socket and its web server on 127.0.0.1
    (each on the first free port from meshcat's defaults, 6000 and 7000)."""

    def __init__(self) -> None:
        super().__init__(host=LOOPBACK)

    def make_app(self) -> Any:
        """meshcat's tornado application, whose ``listen`` binds to 127.0.0.1 only."""
        app = super().make_app()
        app.listen = functools.partial(app.listen, address=LOOPBACK)
        return app


def start_server() -> tuple[subprocess.Popen[bytes], str]:
    """Start the server as the leader of a process group of its own (stop it with
    :func:`bridge.processes.stop_process_group`; it stops by itself once this process is
    gone, even killed); ``(its process, its ZMQ URL)``.

    Raises:
        RuntimeError: it exited before saying where it listens (with what it printed)."""
    errors = tempfile.TemporaryFile()  # a pipe nobody reads could fill up and block it
    process = subprocess.Popen(
        [sys.executable, "-u", "-m", SERVER_MODULE],
        stdout=subprocess.PIPE,
        stderr=errors,
        env=node_environment(),
        start_new_session=True,
    )
    assert process.stdout is not None
    with errors:
        line = process.stdout.readline().decode(errors="replace").strip()
        if not line.startswith("zmq_url="):
            process.kill()
            process.wait()
            errors.seek(0)
            said = errors.read().decode(errors="replace").strip().splitlines()[-1:] or [line]
            raise RuntimeError(f"the meshcat server exited ({process.returncode}): {said[0]}")
    process.stdout.close()
    return process, line.removeprefix("zmq_url=")


def main() -> None:
    """Serve until SIGTERM (or SIGINT, or the process that started it is gone), first
    printing ``zmq_url=URL`` (one line)."""
    exit_with_parent()
    server = LoopbackBridge()
    print(f"zmq_url={server.zmq_url}", flush=True)
    try:
        server.run()
    except KeyboardInterrupt:
        pass


if __name__ == "__main__":
    main()
