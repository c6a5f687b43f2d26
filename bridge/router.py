"""A Zenoh router: the meeting point for engines and brains on several machines.

Nodes on other machines run in ``client`` mode (or as peers) and connect to the router's
endpoint; the router forwards between them. Listening on a non-loopback address prints a
warning: secure such a setup with TLS and access control (``docs/deployment.md``).
"""

from __future__ import annotations

import json
import logging
import threading
from collections.abc import Sequence
from pathlib import Path

import zenoh

from .errors import ConfigError
from .processes import wait_for_stop
from .session import SessionSettings, build_config

log = logging.getLogger("toyroom.bridge")

DEFAULT_ROUTER_ENDPOINT = "tcp/127.0.0.1:7447"


class Router:
    """A Zenoh router session listening on ``listen``; a context manager."""

    def __init__(self, listen: Sequence[str], *, config_file: Path | None = None) -> None:
        settings = SessionSettings(
            mode="router",
            listen=tuple(listen) if listen else None,
            connect=() if config_file is None else None,
            config_file=config_file,
        )
        config = build_config("router", settings)
        try:
            self.session = zenoh.open(config)
        except Exception as err:
            raise ConfigError(f"cannot start a Zenoh router on {', '.join(listen)}: {err}") from None
        configured = json.loads(config.get_json("listen/endpoints"))
        if isinstance(configured, dict):  # per-mode defaults
            configured = configured.get("router", [])
        self.listen = tuple(listen) or tuple(configured or ())
        self._closed = False

    def close(self) -> None:
        """Stop the router; safe to call twice."""
        if not self._closed:
            self._closed = True
            self.session.close()

    def __enter__(self) -> Router:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


def run_router(
    listen: Sequence[str], *, config_file: Path | None = None, stop: threading.Event | None = None
) -> None:
    """Run a router until ``stop`` is set (or forever)."""
    stop = stop or threading.Event()
    with Router(listen, config_file=config_file) as router:
        log.info("router %s listening on %s", router.session.zid(), ", ".join(router.listen))
        print(f"toyroom router listening on {', '.join(router.listen)}", flush=True)
        wait_for_stop(stop)
