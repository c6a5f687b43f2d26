"""``toyroom rate RECORDINGS... --questions FILE.toml`` (``python -m toyroom.rating``): serve
the rating page to participants until interrupted, or save a screenshot of it and exit."""

from __future__ import annotations

import argparse
import logging
import secrets
import sys
import tempfile
import threading
from collections.abc import Sequence
from pathlib import Path
from urllib.parse import urlsplit

from bridge.errors import BridgeError
from bridge.flags import add_log_level, command_parser, configure_logging
from bridge.processes import stop_on_signals, wait_for_stop
from bridge.recording import TraceError, read_trace
from protocol import ProtocolError, check_name
from toyroom.play.recording import complete_only
from toyroom.view.screenshot import screenshot

from .answers import check_answers_path
from .questions import load_study
from .server import LOOPBACK_HOST, RatingServer, RatingSettings, read_or_make_secret

log = logging.getLogger("toyroom.rating")

DEFAULT_LISTEN = "http://127.0.0.1:7450"


def build_parser() -> argparse.ArgumentParser:
    """``python -m toyroom.rating``'s options."""
    parser = command_parser(
        "python -m toyroom.rating",
        "Serve a judgments page (Baker et al. style): participants watch recordings up to each "
        "question's tick and rate beliefs and desires on sliders; answers go to a CSV that "
        "`toyroom fit --judgments` reads.",
    )
    parser.add_argument("recordings", type=Path, nargs="+", metavar="RECORDING", help="trace.jsonl or .mcap")
    parser.add_argument("--questions", type=Path, required=True, metavar="FILE.toml", help="the study")
    parser.add_argument(
        "--out", type=Path, default=Path("ratings.csv"), metavar="FILE.csv", help="answers (appended)"
    )
    parser.add_argument(
        "--participants",
        default="1",
        help="a count N (ids p1..pN) or comma-separated ids; each gets a link of their own",
    )
    parser.add_argument(
        "--secret",
        type=Path,
        metavar="FILE",
        help="the links' secret (default: OUT with .secret; made when missing)",
    )
    parser.add_argument(
        "--listen",
        default=DEFAULT_LISTEN,
        metavar="URL",
        help="http://HOST:PORT to serve (port 0: any free port); a non-loopback host serves a lab network",
    )
    parser.add_argument(
        "--origin", action="append", default=[], metavar="URL", help="another allowed page origin"
    )
    parser.add_argument(
        "--include-incomplete",
        action="store_true",
        help="also ask about toyroom play recordings marked incomplete (left out by default, and listed)",
    )
    parser.add_argument(
        "--screenshot",
        type=Path,
        metavar="FILE.png",
        help="save the first participant's next question page (1000x750, headless Chromium) and exit",
    )
    add_log_level(parser, "WARNING")
    return parser


def parse_listen(url: str) -> tuple[str, int]:
    """``http://HOST:PORT`` as ``(host, port)``; a :class:`BridgeError` naming what is wrong."""
    parts = urlsplit(url)
    if parts.scheme != "http" or not parts.hostname or parts.path not in ("", "/"):
        raise BridgeError(f"--listen takes http://HOST:PORT (e.g. {DEFAULT_LISTEN}), got {url!r}")
    try:
        port = parts.port if parts.port is not None else 7450
    except ValueError:
        raise BridgeError(f"--listen: the port of {url!r} is not a number in 0-65535") from None
    return parts.hostname, port


def participants(value: str) -> tuple[str, ...]:
    """``--participants``: a count (``p1``..``pN``) or comma-separated ids, each checked as
    ``toyroom play`` checks its participants' (:func:`protocol.check_name`: 1-64 letters,
    digits, ``_`` or ``-``; so no ``.`` or ``..``, which a browser's link would resolve away)."""
    if value.strip().isdigit():
        count = int(value)
        if count < 1:
            raise BridgeError("--participants: expected at least 1")
        return tuple(f"p{n}" for n in range(1, count + 1))
    ids = tuple(v.strip() for v in value.split(","))
    try:
        for name in ids:
            check_name(name, "participant")
    except ProtocolError as err:
        raise BridgeError(f"--participants: {err.reason}") from None
    if len(set(ids)) != len(ids):
        raise BridgeError(f"--participants: expected distinct ids, got {value!r}")
    return ids


def settings_from(args: argparse.Namespace) -> RatingSettings:
    """The server's settings: recordings read, the questions checked against them."""
    ids = participants(args.participants)
    check_answers_path(args.out)  # before anything is made beside it
    traces, names = [], []
    args.recordings, left = complete_only(args.recordings, args.include_incomplete)
    for note in left:
        print(f"toyroom rate: left out an incomplete play recording: {note} (--include-incomplete keeps it)")
    if not args.recordings:
        raise BridgeError("no recording left to ask about (every one is an incomplete play recording)")
    for path in args.recordings:
        try:
            traces.append(read_trace(path))
        except TraceError as err:
            raise BridgeError(str(err)) from None
        names.append(path.name.split(".")[0])
    study = load_study(args.questions, traces, names)
    for note in study.skipped:
        print(f"toyroom rate: {note}", flush=True)
    secret_file = args.secret or args.out.with_name(args.out.name + ".secret")
    # a screenshot writes nothing: a throwaway secret unless the study has one already
    shot_only = args.screenshot is not None and not secret_file.exists()
    return RatingSettings(
        study=study,
        traces=traces,
        participants=ids,
        answers=args.out,
        secret=secrets.token_hex(16).encode() if shot_only else read_or_make_secret(secret_file),
        origins=tuple(args.origin),
    )


def replay_seconds(settings: RatingSettings) -> float:
    """Seconds of replay one participant watches: every question's clip, from the recording's
    first tick to the last it shows, at the study's rate."""
    total = 0.0
    for q in settings.study.questions:
        trace = settings.traces[q.recording]
        total += (q.show_until - trace.ticks[0][0].tick) * trace.info.tick_seconds
    return total / settings.study.replay_rate


def _shoot(args: argparse.Namespace, settings: RatingSettings, stop: threading.Event) -> int:
    """Render the first participant's page (consent skipped) into ``--screenshot``."""
    with tempfile.TemporaryDirectory() as scratch:
        # a scratch copy of the answers: a screenshot never writes to the study's file
        copy = Path(scratch) / "answers.csv"
        if args.out.exists():
            copy.write_bytes(args.out.read_bytes())
        shot = RatingSettings(settings.study, settings.traces, settings.participants, copy, settings.secret)
        with RatingServer(shot) as server:
            server.agree(settings.participants[0])  # in the scratch server's memory only
            if not screenshot(server.link(settings.participants[0]), args.screenshot, stop):
                print("toyroom rate: stopped before the screenshot was saved", file=sys.stderr)
                return 1
    print(f"toyroom rate: saved {args.screenshot}", flush=True)
    return 0


def main(argv: Sequence[str] | None = None) -> int:
    """Serve until SIGINT or SIGTERM (or save ``--screenshot`` and exit); 2 on bad input."""
    args = build_parser().parse_args(argv)
    configure_logging(args.log_level)
    stop = threading.Event()
    stop_on_signals(stop)
    try:
        host, port = parse_listen(args.listen)
        settings = settings_from(args)
        if args.screenshot is not None:
            return _shoot(args, settings, stop)
        server = RatingServer(settings, host, port)
    except BridgeError as err:
        print(f"toyroom rate: {err}", file=sys.stderr)
        return 2
    with server:
        if not LOOPBACK_HOST.match(host):
            print(
                f"toyroom rate: WARNING: listening on {host}: other machines on the network can reach "
                "the page; share each link only with its participant (plain http: use a trusted lab "
                "network, or a TLS proxy)",
                file=sys.stderr,
                flush=True,
            )
        count = len(settings.study.questions)
        replay = replay_seconds(settings)
        lines = [
            f"toyroom rate: {count} questions, answers to {args.out}, on {server.url}",
            f"toyroom rate: each participant watches {replay / 60:.1f} min of replay "
            f"({settings.study.replay_rate:g}x real time), besides reading and answering",
        ]
        lines += [f"  {p}: {server.link(p)}" for p in settings.participants]
        print("\n".join([*lines, "toyroom rate: ready"]), flush=True)
        wait_for_stop(stop)
    return 0
