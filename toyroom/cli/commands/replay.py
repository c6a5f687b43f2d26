"""``toyroom replay``: republish a recording (MCAP) on a world so brains and viewers run on it;
the recording is read first (:mod:`toyroom.cli.recordings`)."""

from __future__ import annotations

import argparse
import threading
from pathlib import Path

from bridge.flags import non_negative_int
from bridge.processes import stop_on_signals, wait_for_stop
from bridge.session import add_network_args, settings_from_args

from ..floors import replay_problem
from ..options import strict_option
from ..recordings import checked
from ..subcommand import Subcommand


def options(replaying: argparse.ArgumentParser) -> None:
    """``toyroom replay``'s options."""
    replaying.add_argument("file", type=Path, metavar="FILE.mcap", help="the recording")
    strict_option(replaying)
    replaying.add_argument(
        "--speed", type=float, default=1.0, help="times real time (at least 0.001); 0: as fast as possible"
    )
    replaying.add_argument(
        "--until-tick",
        type=non_negative_int,
        help="stop after this tick, a whole number >= 0 (and keep serving the handshake)",
    )
    replaying.add_argument("--hold", action="store_true", help="keep serving the handshake until interrupted")
    replaying.add_argument(
        "--wait-subscribers",
        type=float,
        default=0.0,
        metavar="S",
        help="first wait up to S s (>= 0) for a subscriber",
    )
    add_network_args(replaying)


def problem(args: argparse.Namespace) -> str | None:
    """``--speed`` or ``--wait-subscribers`` below its floor (:mod:`toyroom.cli.floors`), or ``None``."""
    return replay_problem(args.speed, args.wait_subscribers)


def replay_main(args: argparse.Namespace) -> int:
    """``toyroom replay``: republish a recording until its end (or SIGINT/SIGTERM), then with
    ``--hold`` keep serving its handshake until stopped."""
    from bridge.bridge import Bridge
    from bridge.recording.replay import replay

    recording = checked(args.file, "replay", args.strict)
    if recording is None:
        return 1
    stop = threading.Event()
    stop_on_signals(stop)
    with Bridge(args.world, settings_from_args(args)) as bridge:
        sent = replay(
            bridge,
            recording,
            speed=args.speed,
            stop=stop,
            until_tick=args.until_tick,
            wait_subscribers=args.wait_subscribers,
            resend_minds=args.hold,
        )
        print(f"toyroom replay: {sent} messages from {args.file} on world '{args.world}'", flush=True)
        if args.hold:
            wait_for_stop(stop)
    return 0


COMMAND = Subcommand(
    "replay", "republish an MCAP recording so brains and viewers run on it", options, replay_main, problem
)
