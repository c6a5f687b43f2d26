"""``toyroom record``: record every message of a world to an MCAP file until interrupted."""

from __future__ import annotations

import argparse
import sys
import threading
from pathlib import Path

from bridge.flags import out_file_problem
from bridge.processes import stop_on_signals, wait_for_stop
from bridge.session import SessionSettings, add_network_args, settings_from_args

from ..subcommand import Subcommand


def options(record: argparse.ArgumentParser) -> None:
    """``toyroom record``'s options."""
    record.add_argument("file", type=Path, metavar="FILE.mcap", help="the recording to write")
    add_network_args(record)


def problem(args: argparse.Namespace) -> str | None:
    """The recording to write is a folder or in a missing one (one line), or ``None``."""
    return out_file_problem(args.file, "", make_folder=False)


def record_main(world: str, settings: SessionSettings, path: Path) -> int:
    """Record every message of ``world`` to ``path`` until SIGINT or SIGTERM."""
    from bridge.bridge import Bridge
    from bridge.recording.mcap import McapRecorder

    stop = threading.Event()
    stop_on_signals(stop)
    with Bridge(world, settings) as bridge, McapRecorder(bridge, path) as recorder:
        print(f"toyroom record: world '{world}' to {path}", flush=True)
        wait_for_stop(stop)
        count = recorder.count
    if recorder.error is not None:  # a full disk: what came after the failure is lost
        print(f"toyroom record: {recorder.error}; kept the first {count} messages in {path}", file=sys.stderr)
        return 1
    print(f"toyroom record: {count} messages in {path}")
    return 0


def handle(args: argparse.Namespace) -> int:
    """``toyroom record``: :func:`record_main` on the parsed world and file."""
    return record_main(args.world, settings_from_args(args), args.file)


COMMAND = Subcommand(
    "record", "record every message of a world to MCAP until interrupted", options, handle, problem
)
