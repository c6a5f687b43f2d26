"""``toyroom infer`` and ``toyroom replay``: the commands that take a recording read it first,
under the one policy of :mod:`bridge.recording.readable`, and only then write or publish
anything. A missing file, or one that is no recording, is one line naming it and the
problem (exit 2), with nothing written; a cut-off or damaged one is used as far as it can be
read, with a warning naming the byte offset where it broke and the ticks kept, and refused
with ``--strict`` in one line (exit 1): a file whose end is missing (its footer or closing
MCAP magic) is cut off, even when every message in it is whole. A file that mixes two
worlds is no recording (exit 2)."""

from __future__ import annotations

import argparse
import sys
import threading
from pathlib import Path

from bridge.flags import settings_argv
from bridge.processes import stop_on_signals, wait_for_stop
from bridge.recording.atomic import replacing, write_text
from bridge.recording.events import write_events_csv
from bridge.recording.readable import Recording, read_recording
from bridge.recording.trace import episode_of, write_trace
from bridge.session import settings_from_args

from .commands import exec_node


def checked(path: Path, command: str, strict: bool) -> Recording | None:
    """The readable part of the recording at ``path``, after a warning when it is cut off or
    damaged; ``None`` when it is and ``strict`` refuses it (one line on stderr, either way).

    Raises:
        RecordingError: the file is missing, of neither format, holds no message, or mixes
            two worlds.
    """
    recording = read_recording(path)
    if recording.cut is None:
        return recording
    if strict:
        line = f"refused: {recording.cut.warning()} (--strict refuses a recording that is not whole)"
        print(f"toyroom {command}: {line}", file=sys.stderr, flush=True)
        return None
    print(f"toyroom {command}: warning: {recording.cut.warning()}", file=sys.stderr, flush=True)
    return recording


def _same_file(a: Path, b: Path) -> bool:
    return a.resolve() == b.resolve()


def _recorded_settings(args: argparse.Namespace, recording: Recording) -> Path | None:
    """The settings recorded with the run: an MCAP file's metadata (written into ``--out``)
    or the ``settings.toml`` beside a ``trace.jsonl``."""
    if recording.format == "mcap":
        from bridge.recording.mcap import recorded_settings

        text = recorded_settings(args.trace)
        if text is None:
            return None
        path = args.out / "recorded-settings.toml"
        write_text(path, text)
        return path
    beside = args.trace.parent / "settings.toml"
    return beside if beside.is_file() else None


def infer_main(args: argparse.Namespace) -> int:
    """``toyroom infer``: a recording through a fresh brain, with the settings recorded with
    it unless ``--settings`` names others (``--set`` applies on top of either). Writes
    ``trace.jsonl`` (what was readable of the recording) and ``events.csv`` into ``--out``,
    then the brain writes ``mind.csv``, the figures and ``report.md`` there."""
    recording = checked(args.trace, "infer", args.strict)
    if recording is None:
        return 1
    messages = list(recording.messages())
    episode_of(messages, args.trace)  # no handshake or state: one line naming the recording
    args.out.mkdir(parents=True, exist_ok=True)
    trace = args.out / "trace.jsonl"
    if _same_file(trace, args.trace):
        trace = args.trace  # inferring into the run's own folder: the brain reads it in place
    else:  # each file whole or not at all: a full disk is one line, nothing half written
        with replacing(trace) as partial:
            write_trace(messages, partial)
    with replacing(args.out / "events.csv") as partial:
        rows = write_events_csv(trace, partial)
    print(f"toyroom infer: {len(messages)} messages; events.csv with {rows} rows in {args.out}", flush=True)
    recorded = _recorded_settings(args, recording)
    settings = args.settings
    if settings is None and recorded is not None:
        print(f"toyroom infer: using the settings recorded with the run ({recorded})", flush=True)
        settings = recorded
    argv = ["infer", str(trace), "--out", str(args.out), "--observer", args.observer]
    argv += ["--note", recording.cut.note()] if recording.cut is not None else []
    argv += ["--log-level", args.log_level] if args.log_level else []
    argv += settings_argv(settings, args.overrides)
    return exec_node("brain", argv, prog="toyroom infer")


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
