"""``events.csv`` read off a trace: the same rows however the recorder interleaved a
command and its statuses (a status may be recorded before the command it answers)."""

from __future__ import annotations

import csv
from pathlib import Path

import msgspec
from support import golden_examples

from bridge.recording.events import write_events_csv
from bridge.recording.trace import trace_line
from protocol import CommandState, CommandStatus, Keys, Message, Request, RobotCommand

KEYS = Keys("events-test")


def _write(path: Path, records: list[tuple[str, Message]]) -> None:
    path.write_text("".join(trace_line(key, message) + "\n" for key, message in records), encoding="utf-8")


def _status(command: str, state: CommandState, tick: int, **extra: object) -> tuple[str, Message]:
    return KEYS.status("robot"), CommandStatus(
        command=command, robot="robot", state=state, tick=tick, **extra
    )


def _details(path: Path) -> list[str]:
    with path.open(newline="") as handle:
        return [row["detail"] for row in csv.DictReader(handle) if row["kind"] == "command"]


def test_a_status_recorded_before_its_command_gets_the_commands_kind(tmp_path: Path) -> None:
    request = RobotCommand(id="c4", robot="robot", action=Request(person="A2", item="skate"))
    sent = (KEYS.command("robot"), request)
    accepted = _status("c4", CommandState.ACCEPTED, 12)
    running = _status("c4", CommandState.RUNNING, 12)
    succeeded = _status("c4", CommandState.SUCCEEDED, 14, answer=True)
    in_order, raced = tmp_path / "in-order.jsonl", tmp_path / "raced.jsonl"
    _write(in_order, [sent, accepted, running, succeeded])
    _write(raced, [accepted, sent, running, succeeded])  # the engine's answer arrived first

    rows = {}
    for trace in (in_order, raced):
        out = trace.with_suffix(".csv")
        assert write_events_csv(trace, out) == 3
        rows[trace.stem] = _details(out)
    assert rows["raced"] == ["c4 request accepted", "c4 request running", "c4 request succeeded answer yes"]
    assert rows["raced"] == rows["in-order"]


def test_a_reused_id_matches_the_nearest_command(tmp_path: Path) -> None:
    first = RobotCommand(id="c1", robot="robot", action=Request(person="A2", item="skate"))
    second = RobotCommand(id="c1", robot="robot", action=Request(person="A1", item="ball"))
    key = KEYS.command("robot")
    trace = tmp_path / "two-episodes.jsonl"
    _write(
        trace,
        [
            (key, first),
            _status("c1", CommandState.FAILED, 3, reason="out of reach"),
            _status("c1", CommandState.ACCEPTED, 5),  # the second episode's, before its command
            (key, second),
        ],
    )
    write_events_csv(trace, tmp_path / "events.csv")
    with (tmp_path / "events.csv").open(newline="") as handle:
        rows = [(r["item"], r["detail"]) for r in csv.DictReader(handle)]
    assert rows == [("skate", "c1 request failed: out of reach"), ("ball", "c1 request accepted")]


def test_rows_of_one_tick_come_in_one_order_however_they_were_recorded(tmp_path: Path) -> None:
    """The engine's events, then its command statuses, then the brain's task rows: the three
    reach a recorder in any order, and a run's events.csv must be the same each time."""
    golden = golden_examples()
    mind = msgspec.structs.replace(golden["mind"], tick=42)
    event = msgspec.structs.replace(golden["event"], tick=42)
    records = [(KEYS.mind, mind), (KEYS.events, event), _status("c1", CommandState.ACCEPTED, 42)]
    written = set()
    for shift in range(len(records)):
        trace = tmp_path / f"order-{shift}.jsonl"
        _write(trace, records[shift:] + records[:shift])
        write_events_csv(trace, trace.with_suffix(".csv"))
        with trace.with_suffix(".csv").open(newline="") as handle:
            kinds = [row["kind"] for row in csv.DictReader(handle)]
        assert kinds == ["take", "command", "task"], (
            f"recorded order {shift}: expected take, command, task; got {kinds}"
        )
        written.add(trace.with_suffix(".csv").read_bytes())
    assert len(written) == 1, "the same rows recorded in another order gave another events.csv"
