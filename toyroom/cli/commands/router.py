"""``toyroom router``: a Zenoh router for multi-machine setups, until interrupted."""

from __future__ import annotations

import argparse
import logging
import threading
from collections.abc import Sequence
from pathlib import Path

from bridge.processes import stop_on_signals, wait_for_stop

from ..subcommand import Subcommand

log = logging.getLogger("toyroom.bridge")


def options(router: argparse.ArgumentParser) -> None:
    """``toyroom router``'s options."""
    router.add_argument(
        "--listen", action="append", metavar="ENDPOINT", help="endpoint (default: tcp/127.0.0.1:7447)"
    )
    router.add_argument("--zenoh-config", type=Path, help="a Zenoh JSON5 config file to start from")


def router_main(listen: Sequence[str], config_file: Path | None) -> int:
    """Run a Zenoh router until interrupted (a warning when it listens beyond loopback:
    secure such a setup with TLS and access control, ``docs/deployment.md``)."""
    from bridge.session import Router

    stop = threading.Event()
    stop_on_signals(stop)
    with Router(listen, config_file=config_file) as router:
        log.info("router %s listening on %s", router.session.zid(), ", ".join(router.listen))
        print(f"toyroom router listening on {', '.join(router.listen)}", flush=True)
        wait_for_stop(stop)
    return 0


def handle(args: argparse.Namespace) -> int:
    """``toyroom router``: listen where told (default: loopback, unless a config file says where)."""
    from bridge.session import DEFAULT_ROUTER_ENDPOINT

    default = [] if args.zenoh_config else [DEFAULT_ROUTER_ENDPOINT]  # a config file says where
    return router_main(args.listen or default, args.zenoh_config)


COMMAND = Subcommand("router", "run a Zenoh router for multi-machine setups", options, handle)
