"""``python -m toyroom.gateway`` (``toyroom gateway``): the gateway until SIGINT or SIGTERM."""

from __future__ import annotations

import argparse
import math
import os
import sys
import threading
from collections.abc import Sequence
from pathlib import Path

from bridge.errors import BridgeError
from bridge.flags import add_log_level, command_parser, configure_logging
from bridge.processes import stop_on_signals, wait_for_stop
from bridge.session import SessionSettings, world_problem

from .outbox import MAX_QUEUED_FRAMES, QueueLimits
from .server import DEFAULT_URL, Gateway, GatewaySettings

MIN_PING_S = 0.1
"""The shortest ``--ping`` (s): a client must answer a ping within that time or be dropped."""
PING_FLOOR_WHY = "a client that takes one slow frame to answer a ping would be dropped"


def build_parser() -> argparse.ArgumentParser:
    """The parser of ``python -m toyroom.gateway``."""
    parser = command_parser(
        "python -m toyroom.gateway",
        "carry one world's protocol over a WebSocket, for engines without Zenoh (Unity, C#)",
    )
    parser.add_argument("--world", default="default", help="world name: the key prefix toyroom/WORLD/")
    parser.add_argument(
        "--listen", default=DEFAULT_URL, metavar="URL", help="ws://HOST:PORT to serve (port 0: any free port)"
    )
    parser.add_argument("--token", type=Path, metavar="FILE", help="clients must send this file's secret")
    parser.add_argument(
        "--origin", action="append", default=[], help="a browser origin allowed besides loopback (repeatable)"
    )
    parser.add_argument(
        "--ping",
        type=float,
        default=0.5,
        metavar="S",
        help="seconds between pings, at least 0.1 (a silent client is dropped)",
    )
    parser.add_argument(
        "--queue-frames",
        type=int,
        default=MAX_QUEUED_FRAMES,
        metavar="N",
        help="frames a client may have waiting to be sent; a client slower than that is dropped",
    )
    network = parser.add_argument_group("Zenoh (default: loopback only, no multicast)")
    network.add_argument("--zenoh-config", type=Path, help="a Zenoh JSON5 config file to start from")
    network.add_argument("--mode", choices=("peer", "client", "router"), help="Zenoh mode")
    network.add_argument(
        "--connect", action="append", metavar="ENDPOINT", help="Zenoh endpoint to connect to"
    )
    network.add_argument(
        "--zenoh-listen", action="append", metavar="ENDPOINT", help="Zenoh endpoint to listen on"
    )
    add_log_level(parser)
    return parser


def settings_from(args: argparse.Namespace) -> GatewaySettings:
    """The gateway's settings from its parsed arguments."""
    session = SessionSettings(
        mode=args.mode,
        listen=tuple(args.zenoh_listen) if args.zenoh_listen else None,
        connect=tuple(args.connect) if args.connect else None,
        config_file=args.zenoh_config,
    )
    if not (MIN_PING_S <= args.ping < math.inf):
        raise BridgeError(f"--ping must be at least {MIN_PING_S:g} s ({PING_FLOOR_WHY}), got {args.ping}")
    if args.queue_frames < 1:
        raise BridgeError(f"--queue-frames must be a whole number of at least 1, got {args.queue_frames}")
    return GatewaySettings(
        world=args.world,
        listen=args.listen,
        token_file=args.token,
        origins=tuple(args.origin),
        ping=args.ping,
        queue=QueueLimits(frames=args.queue_frames),
        session=session,
    )


def main(argv: Sequence[str] | None = None) -> int:
    """Run the gateway node on ``argv`` until interrupted; the exit status."""
    args = build_parser().parse_args(argv)
    configure_logging(args.log_level)
    if (problem := world_problem(args.world)) is not None:
        print(f"toyroom gateway: {problem}", file=sys.stderr)
        return 2
    stop = threading.Event()
    stop_on_signals(stop)
    try:
        gateway = Gateway(settings_from(args))
    except BridgeError as err:
        print(f"toyroom gateway: {err}", file=sys.stderr)
        return 2
    with gateway:
        # one write, so that no log line lands inside it (toyroom run reads the URL from it)
        os.write(1, f"toyroom gateway: world '{args.world}' on {gateway.url} (ready)\n".encode())
        wait_for_stop(stop)
    return 0
