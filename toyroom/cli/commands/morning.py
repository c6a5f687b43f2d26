"""``toyroom morning RUN [--out FILE]``: the next morning of a household from a finished run.

A household lived by hand (docs/usage.md, "A household lived by hand") is
``toyroom generate --day 1``, ``toyroom run --memory FILE``, then this command, then
``toyroom generate --day 2 --morning FILE`` and so on. It reads the run's recording
(``RUN/trace.jsonl``, or a ``trace.jsonl`` or ``.mcap`` file named directly), takes the last
``engine/truth`` of its episode and writes it as a :class:`protocol.Morning`
(:func:`protocol.morning_of`, as ``toyroom eval --days`` does), naming the household
(``Scene.household.id``) and map (the scene's name) the generator checks it against.

Refused in one line, exit 2: no recording, a run that did not finish (its ``FAILED`` note, or
a cut recording: its last truth is not the day's end), an episode that names no household,
one with no truth, and an ``--out`` that is a folder or in a missing one.
"""

from __future__ import annotations

import sys
from collections.abc import Sequence
from pathlib import Path

import msgspec

from bridge.errors import BridgeError
from bridge.flags import command_parser, out_file_problem
from bridge.recording.atomic import output_error, write_bytes
from bridge.recording.readable import read_recording
from protocol import EngineInfo, Morning, Truth, morning_of

FAILED = "FAILED"
"""The note ``toyroom run`` leaves in the folder of a run that did not finish."""


class MorningProblem(BridgeError):
    """A run that gives no morning: one line saying why."""


def recording_of(run: Path) -> Path:
    """The recording of ``run``: a run folder's ``trace.jsonl``, or the file named.

    Raises:
        MorningProblem: a folder with no ``trace.jsonl``, or a run that did not finish.
    """
    if not run.is_dir():
        return run
    if (run / FAILED).exists():
        raise MorningProblem(
            f"{run}: the run did not finish (see {run / FAILED}): its last tick is not the day's end"
        )
    if not (run / "trace.jsonl").is_file():
        raise MorningProblem(f"{run}: no trace.jsonl: not a toyroom run folder")
    return run / "trace.jsonl"


def morning_of_run(run: Path) -> tuple[Morning, int, int]:
    """The morning after ``run``'s day, with that day and the tick its end was read at.

    Raises:
        MorningProblem, RecordingError: ``run`` gives no morning (one line why).
    """
    path = recording_of(run)
    recording = read_recording(path)
    if recording.cut is not None:
        raise MorningProblem(f"{recording.cut.warning()}: its last tick is not the day's end")
    info: EngineInfo | None = None
    truths: list[Truth] = []
    for _, message in recording.messages():
        if isinstance(message, EngineInfo):
            info, truths = message, []  # an engine reset: a new episode from here
        elif isinstance(message, Truth):
            truths.append(message)
    if info is None:
        raise MorningProblem(f"{path}: no engine handshake (engine/info): not a run's recording")
    household = info.scene.household
    if household is None:
        raise MorningProblem(
            f"{path}: the episode {info.scenario!r} names no household ([household] in its "
            "scenario): it starts no next day"
        )
    truths = [t for t in truths if t.episode == info.episode] or truths
    if not truths:
        raise MorningProblem(f"{path}: no engine/truth: the engine sent no truth to read a morning from")
    last = max(truths, key=lambda t: t.tick)
    named = msgspec.structs.replace(morning_of(last), household=household.id, map=info.scene.name)
    return named, household.day, last.tick


def main(argv: Sequence[str] | None = None) -> int:
    """``toyroom morning RUN [--out FILE]`` (also ``python -m toyroom.cli.commands.morning``)."""
    parser = command_parser(
        "toyroom morning",
        "write the next morning of a household (JSON, for toyroom generate --day D --morning FILE) "
        "from a finished run: the last engine/truth of its trace.jsonl or .mcap",
    )
    parser.add_argument(
        "run", type=Path, metavar="RUN", help="a toyroom run folder, or its trace.jsonl or .mcap"
    )
    parser.add_argument("--out", type=Path, help="the morning file to write (default: print it)")
    args = parser.parse_args(argv)
    if args.out is not None and (problem := out_file_problem(args.out, make_folder=False)) is not None:
        print(f"{parser.prog}: {problem}", file=sys.stderr)
        return 2
    try:
        morning, day, tick = morning_of_run(args.run)
    except BridgeError as err:
        print(f"{parser.prog}: {err}", file=sys.stderr)
        return 2
    data = msgspec.json.format(msgspec.json.encode(morning), indent=1) + b"\n"
    if args.out is None:
        sys.stdout.write(data.decode())
        return 0
    try:
        write_bytes(args.out, data)
    except OSError as err:
        print(f"{parser.prog}: {output_error(err)}", file=sys.stderr)
        return 1
    print(
        f"wrote {args.out}: household {morning.household!r} on {morning.map}, day {day}'s end (tick {tick})"
    )
    return 0


if __name__ == "__main__":
    sys.exit(main())
