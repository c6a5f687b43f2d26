"""``python -m toyroom.play`` (``toyroom play --scenario S --as A1``): serve the participants'
pages until every participant's world has ended (or SIGINT / SIGTERM, which ends those still
running, their recordings marked incomplete). Prints one link per participant, one a line
(``toyroom play: participant p1: http://...``), and, for each world that ends, where its
recording is and whether it is complete."""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import re
import subprocess
import sys
import threading
from collections.abc import Sequence
from pathlib import Path

import msgspec

from bridge.errors import BridgeError
from bridge.flags import add_log_level, command_parser, configure_logging
from bridge.processes import stop_on_signals, wait_for_stop
from bridge.session import LOOPBACK
from protocol import ProtocolError, Study, check_name

from .config import PlayConfig
from .server import PlayServer, is_loopback_host, parse_listen
from .timing import held_rate
from .world import PlayWorld

DEFAULT_LISTEN = f"{LOOPBACK}:8470"


def build_parser() -> argparse.ArgumentParser:
    """The parser of ``python -m toyroom.play``."""
    parser = command_parser(
        "python -m toyroom.play",
        "Let participants play one person of a scenario in their browser, each in a world of their "
        "own (engine in real time, brain and robot as in toyroom run), every world recorded to MCAP.",
    )
    parser.add_argument("--scenario", default="paper-robot", help="scenario name or .toml path")
    parser.add_argument(
        "--as", dest="person", default="A1", metavar="PERSON", help="the person participants play"
    )
    parser.add_argument(
        "--participants",
        default="1",
        metavar="N|IDS",
        help="how many participants (ids p1..pN), or their ids, comma-separated (ann,bob)",
    )
    parser.add_argument(
        "--out",
        type=Path,
        default=Path("out/play"),
        help="OUT/<participant>.mcap, the nodes' logs and outputs in OUT/<participant>/",
    )
    parser.add_argument(
        "--listen",
        default=DEFAULT_LISTEN,
        metavar="HOST:PORT",
        help="where to serve the pages (port 0: any free port; not loopback: "
        "other machines reach it, a lab network only)",
    )
    parser.add_argument("--rate", type=float, default=1.0, help="engine speed, x wall-clock")
    parser.add_argument("--seed", type=int, default=0, help="episode seed")
    parser.add_argument(
        "--grace",
        type=float,
        default=60.0,
        metavar="S",
        help="seconds a closed page may take to come back (a reload) before its world ends, incomplete",
    )
    add_log_level(parser)
    return parser


def _quiet_websockets(level: str) -> None:
    """The websockets library's INFO lines (every connection) only at DEBUG."""
    import logging

    if level != "DEBUG":
        logging.getLogger("websockets").setLevel(logging.WARNING)


def _participants(text: str) -> list[str]:
    """``--participants``: a count (ids ``p1``..``pN``) or comma-separated ids, checked."""
    if text.strip().isdigit():
        count = int(text)
        if count < 1:
            raise BridgeError(f"--participants must be at least 1, got {count}")
        names = [f"p{n}" for n in range(1, count + 1)]
    else:
        names = [name.strip() for name in text.split(",") if name.strip()]
    for name in names:
        check_name(name, "participant")
    if not names or len(set(names)) != len(names):
        raise BridgeError(f"--participants: give a count or distinct ids, got {text!r}")
    return names


def _config(args: argparse.Namespace) -> PlayConfig:
    if not args.rate > 0:
        raise BridgeError(f"--rate must be > 0, got {args.rate}")
    if not args.grace >= 0:
        raise BridgeError(f"--grace must be >= 0 seconds, got {args.grace}")
    if not re.fullmatch(r"[A-Za-z][A-Za-z0-9_-]{0,63}", args.person):
        raise BridgeError(f"--as takes a person id such as A1, got {args.person!r}")
    return PlayConfig(
        scenario=args.scenario,
        person=args.person,
        out=args.out,
        rate=args.rate,
        seed=args.seed,
        grace=args.grace,
        log_level=args.log_level if args.log_level != "INFO" else "WARNING",
    )


def _check_scenario(config: PlayConfig) -> PlayConfig:
    """Ask sim2d (a process: the application never imports it) for the scenario's scene and
    ``[study]``, and check that ``--as`` names one of its people; the config with the study.

    Raises:
        BridgeError: the scenario cannot be loaded (sim2d's reason), or has no such person.
    """
    command = [sys.executable, "-m", "sim2d", "scene", "--scenario", config.scenario]
    command += ["--seed", str(config.seed), "--study"]
    result = subprocess.run(command, capture_output=True, text=True, timeout=120, check=False)
    if result.returncode != 0:
        lines = [line.removeprefix("sim2d: ") for line in result.stderr.splitlines() if line.strip()]
        raise BridgeError(f"--scenario {config.scenario}: {lines[-1] if lines else result.returncode}")
    read = json.loads(result.stdout)
    people = [a["id"] for a in read["scene"]["agents"] if a["kind"] == "person"]
    if config.person not in people:
        raise BridgeError(
            f"--as {config.person}: no such person in '{config.scenario}' (people: {', '.join(people)})"
        )
    study = msgspec.convert(read["study"], Study) if read["study"] is not None else None
    return dataclasses.replace(config, study=study)


def _terms(config: PlayConfig) -> str:
    """The study's terms in a line: the goal and how long a world may run."""
    study = config.study
    if study is None:
        return "no [study] section: no instructions or goal; each world runs to the scenario's end"
    goal = f"goal: {study.goal.rstrip('.')}" if study.goal else "no goal stated"
    if study.time_limit is None:
        return f"{goal}; each world runs until the goal or the scenario's end"
    minutes = study.time_limit / config.rate / 60
    return (
        f"{goal}; each world ends at the goal or after {study.time_limit:g} s of world time "
        f"({minutes:.1f} min at --rate {config.rate:g})"
    )


def _report(world: PlayWorld) -> None:
    outcome = world.outcome.value if world.outcome is not None else "incomplete"
    kept = f"complete, {outcome}: {world.ended}" if world.complete else f"incomplete: {world.ended}"
    if not world.recording.exists():
        print(
            f"toyroom play: participant {world.participant}: no recording (the page never opened)", flush=True
        )
        return
    held = held_rate(world.recording, world.config.rate, world.tick_seconds)
    speed = f"; the engine ran at {held:.2f} of its rate" if held is not None else ""
    if world.world_time is not None:
        speed += f"; {world.world_time:.0f} s of world time"
    print(
        f"toyroom play: participant {world.participant}: recording {world.recording} ({kept}{speed})",
        flush=True,
    )


def _follow(server: PlayServer, stop: threading.Event) -> None:
    """End the worlds whose episode ended, whose node failed or whose page stayed away; return
    when every world has ended or ``stop`` is set."""
    while not stop.is_set():
        for world in server.worlds.values():
            if world.ended is not None or world.bridge is None:
                continue
            problem = world.failed()
            if world.goal.outcome is not None:  # the study's goal met, or its time limit passed
                world.end(world.goal.reason(), world.goal.outcome)
            elif world.brain_finished():
                outcome = world.goal.finish()
                world.end(world.goal.reason(), outcome)
            elif problem is not None:
                world.end(problem)
            elif world.abandoned():
                world.end(f"the page was closed (no reload within {server.config.grace:g} s)")
            else:
                continue
            _report(world)
        if all(w.ended is not None for w in server.worlds.values()):
            return
        wait_for_stop(stop, 0.5)


def main(argv: Sequence[str] | None = None) -> int:
    """Run the play node on ``argv`` until interrupted; the exit status."""
    args = build_parser().parse_args(argv)
    configure_logging(args.log_level)
    _quiet_websockets(args.log_level)
    stop = threading.Event()
    stop_on_signals(stop)
    try:
        config = _config(args)
        participants = _participants(args.participants)
        config = _check_scenario(config)
        host, _ = parse_listen(args.listen)
        config.out.mkdir(parents=True, exist_ok=True)
        server = PlayServer(config, participants, args.listen, f"play{os.getpid()}")
    except (BridgeError, ValueError, ProtocolError) as err:
        print(f"toyroom play: {err}", file=sys.stderr)
        return 2
    with server:
        if not is_loopback_host(host):
            print(
                f"toyroom play: warning: serving on {args.listen} ({server.origin}): other machines can "
                "reach it; use it on a lab network you trust (the links' tokens are the only lock, "
                "over plain HTTP)",
                file=sys.stderr,
                flush=True,
            )
        print(f"toyroom play: scenario '{config.scenario}' as {config.person} on {server.origin}", flush=True)
        print(f"toyroom play: {_terms(config)}", flush=True)
        for participant in participants:
            print(f"toyroom play: participant {participant}: {server.link(participant)}", flush=True)
        _follow(server, stop)
    for world in server.worlds.values():
        if not world.complete and world.ended == "the server was stopped":
            _report(world)
    return 0
