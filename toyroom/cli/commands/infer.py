"""``toyroom infer``: infer minds from a recording (``trace.jsonl`` or ``.mcap``) with a fresh
brain, no engine needed; the recording is read first (:mod:`toyroom.cli.recordings`)."""

from __future__ import annotations

import argparse
from pathlib import Path

from bridge.flags import add_settings_args, settings_argv
from bridge.recording.atomic import replacing, write_text
from bridge.recording.events import write_events_csv
from bridge.recording.readable import Recording
from bridge.recording.trace import episode_of, write_trace

from ..options import observer_option, strict_option
from ..recordings import checked
from ..subcommand import Subcommand
from .nodes import exec_node


def options(infer: argparse.ArgumentParser) -> None:
    """``toyroom infer``'s options."""
    infer.add_argument("trace", type=Path, help="a trace.jsonl or .mcap written by toyroom run")
    infer.add_argument("--out", type=Path, required=True, help="directory for mind.csv, figures, report.md")
    observer_option(infer, "the person model to infer with")
    strict_option(infer)
    add_settings_args(infer)


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


COMMAND = Subcommand(
    "infer",
    "infer minds from a recording (trace.jsonl or .mcap), no engine needed",
    options,
    infer_main,
    out_folder=True,
)
