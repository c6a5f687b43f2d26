"""``events.csv``: every discrete event of a run, read off its trace.

Header ``tick,actor,kind,item,location,target,detail``. Engine events keep their kind
(``enter``, ``leave``, ``take``, ``drop``, ``play``, ``stop``, ``give``, ``say``,
``request``, ``reply``, ``waypoint``); every robot command status is a row of kind
``command`` whose ``detail`` reads ``<id> <action> <state>`` (and the reason or answer), with
the command's item, location (a location id, or a cell as ``col,row``) and target person.
A robot's tasks, read off the brain's ``mind`` messages, are rows of kind ``task`` whose
``detail`` reads ``begin <task>: <what>`` when one begins, and ``done <task>: <what>`` or
``dropped <task>: <what> (<why>)`` when it ends (protocol 1.3's ``robots[].ended``); a move
the robot reads as a likely deception is a row of kind ``deception`` (actor the mover, target
the person deceived) at the first tick it reads it in the run (``robots[].deceptions``).
"""

from __future__ import annotations

import csv
from dataclasses import dataclass
from pathlib import Path

from protocol import (
    CommandStatus,
    Event,
    Give,
    Mind,
    Navigate,
    Pick,
    Place,
    Request,
    RobotCommand,
    Say,
    UnknownAction,
)

from .trace import trace_records

HEADER = ("tick", "actor", "kind", "item", "location", "target", "detail")


@dataclass(frozen=True)
class EventRow:
    """One row of ``events.csv``: a discrete event of the run (the module's header, column by column)."""

    tick: int
    actor: str
    kind: str
    item: str = ""
    location: str = ""
    target: str = ""
    detail: str = ""

    def cells(self) -> tuple[str, ...]:
        return (str(self.tick), self.actor, self.kind, self.item, self.location, self.target, self.detail)


def _event_row(event: Event) -> EventRow:
    detail = event.detail
    if event.label is not None:
        detail = event.label
    elif event.answer is not None:
        detail = "yes" if event.answer else "no"
    elif event.offer is not None:
        detail = f"offer {event.offer}"
    return EventRow(
        event.tick,
        event.actor,
        str(event.kind),
        event.item or "",
        event.location or "",
        event.target or "",
        detail,
    )


def _status_row(status: CommandStatus, command: RobotCommand | None) -> EventRow:
    action = command.action if command is not None else None
    if action is None:
        kind = "?"
    else:
        kind = action.kind if isinstance(action, UnknownAction) else str(type(action).__struct_config__.tag)
    item = location = target = ""
    if isinstance(action, Navigate):
        location = f"{action.cell.col},{action.cell.row}"
    elif isinstance(action, Pick):
        item = action.item
    elif isinstance(action, Place):
        location = action.location
    elif isinstance(action, Give):
        target = action.person
    elif isinstance(action, Say):
        item, target, location = action.item, action.person, action.location or ""
    elif isinstance(action, Request):
        item, target = action.item, action.person
    detail = f"{status.command} {kind} {status.state.value}"
    if status.reason:
        detail += f": {status.reason}"
    if status.answer is not None:
        detail += f" answer {'yes' if status.answer else 'no'}"
    return EventRow(status.tick, status.robot, "command", item, location, target, detail)


IDLE = ("idle", "go home")
"""Robot activities that are not tasks."""


def _task_rows(
    mind: Mind, last: dict[str, tuple[str, str]], last_deceptions: set[tuple[str, str, str]]
) -> list[EventRow]:
    """The ``task`` rows of one mind message: a task that ended, and one that began (its
    activity differs from the robot's in the last mind, ``last``, which this updates), and a
    ``deception`` row for each likely deception the robot reads for the first time in the run
    (``last_deceptions``: those read so far, updated too)."""
    rows = []
    for activity in mind.robots:
        ended = activity.ended
        if ended is not None:
            detail = f"{ended.outcome.value} {ended.task}: {ended.detail}"
            rows.append(
                EventRow(
                    mind.tick,
                    activity.robot,
                    "task",
                    detail=detail + (f" ({ended.reason})" if ended.reason else ""),
                )
            )
        for d in activity.deceptions:
            if (d.mover, d.person, d.item) not in last_deceptions:
                detail = (
                    f"likely deception (p {d.p:.2f}): {d.mover} moved the {d.item} {d.person} wants, "
                    f"believing {d.person} did not see"
                )
                rows.append(EventRow(mind.tick, d.mover, "deception", d.item, "", d.person, detail))
        last_deceptions.update((d.mover, d.person, d.item) for d in activity.deceptions)
        now = (activity.task, activity.detail)
        if activity.task not in IDLE and now != last.get(activity.robot):
            rows.append(
                EventRow(
                    mind.tick, activity.robot, "task", detail=f"begin {activity.task}: {activity.detail}"
                )
            )
        last[activity.robot] = now
    return rows


def _nearest(sent: list[tuple[int, RobotCommand]], order: int) -> RobotCommand | None:
    """Of the commands recorded with a status's id (``(order, command)`` in trace order), the
    one recorded nearest to the status (before it on a tie): the recorder writes messages as
    they arrive, so a status may land before the command it answers, and a trace of several
    episodes may reuse an id."""
    if not sent:
        return None
    return min(sent, key=lambda c: (abs(c[0] - order), c[0] > order))[1]


EVENT, STATUS, MIND = range(3)
"""Within a tick, the engine's events come first, then its command statuses, then the rows
read off the brain's minds, each in the order recorded: each has one publisher, whose order
holds, while the three reach a recorder in any order (so a run's rows are the same each time)."""


def event_rows(trace: Path) -> list[EventRow]:
    """The rows of a trace, in the order things happened: by tick, then (:data:`EVENT`,
    :data:`STATUS`, :data:`MIND`) as recorded. A status is matched to its command whatever the
    order the two were recorded in."""
    records = [(order, message) for order, _, message in trace_records(trace, strict=False)]
    commands: dict[tuple[str, str], list[tuple[int, RobotCommand]]] = {}
    for order, message in records:
        if isinstance(message, RobotCommand):
            commands.setdefault((message.robot, message.id), []).append((order, message))
    rows: list[tuple[int, int, int, EventRow]] = []
    last: dict[str, tuple[str, str]] = {}
    deceived: set[tuple[str, str, str]] = set()
    for order, message in records:
        if isinstance(message, Mind):
            rows += [(message.tick, MIND, order, row) for row in _task_rows(message, last, deceived)]
        elif isinstance(message, Event):
            rows.append((message.tick, EVENT, order, _event_row(message)))
        elif isinstance(message, CommandStatus):
            command = _nearest(commands.get((message.robot, message.command), []), order)
            rows.append((message.tick, STATUS, order, _status_row(message, command)))
    rows.sort(key=lambda r: r[:3])
    return [row for *_, row in rows]


def write_events_csv(trace: Path, out: Path) -> int:
    """Write ``events.csv`` from a trace; return the number of rows."""
    rows = event_rows(trace)
    with out.open("w", encoding="utf-8", newline="") as handle:
        writer = csv.writer(handle, lineterminator="\n")
        writer.writerow(HEADER)
        writer.writerows(row.cells() for row in rows)
    return len(rows)
