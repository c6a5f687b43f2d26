"""How the robot's checks drive it: a command that must succeed, a walk to a cell or a
person, the farthest cell, and statuses shown in a message."""

from __future__ import annotations

from protocol import Action, Cell, CommandState, CommandStatus, GridCell, Navigate
from protocol.carry import walking_distances

from .probe import CheckFailed, Probe


def shown(statuses: list[CommandStatus]) -> list[str]:
    """Statuses as ``state(reason)`` for a message."""
    return [f"{s.state.value}({s.reason})" if s.reason else s.state.value for s in statuses]


def far_cell(probe: Probe) -> tuple[GridCell, int]:
    """The walkable cell farthest from the robot, and its walking distance."""
    assert probe.info is not None and probe.robot is not None
    distances = walking_distances(probe.info.scene.walkable(), [probe.cell_of(probe.robot)])
    return max(distances.items(), key=lambda kv: (kv[1], kv[0]))


def walk_far(probe: Probe, col: int, row: int) -> tuple[str, GridCell]:
    """Send the robot to the walkable cell farthest from ``(col, row)`` as the crow flies
    (in cells along each axis); the command's id and that cell."""
    assert probe.info is not None
    far = max(probe.info.scene.walkable(), key=lambda c: abs(c[0] - col) + abs(c[1] - row))
    return probe.send(Navigate(cell=Cell(*far))), far


def succeed(probe: Probe, action: Action, what: str) -> list[CommandStatus]:
    """Send ``action`` and step until it ends; its statuses, failing unless it succeeded."""
    statuses = probe.command(action)
    if statuses[-1].state is not CommandState.SUCCEEDED:
        raise CheckFailed(f"{what}: expected succeeded, got {shown(statuses)}")
    return statuses


def holding(probe: Probe, agent: str) -> str | None:
    """The item ``agent`` holds in the newest state."""
    return next((a.holding for a in probe.latest().agents if a.id == agent), None)


def go(probe: Probe, cell: GridCell, what: str) -> None:
    """Walk the robot to ``cell`` (``what`` it goes there for, in a failure's message)."""
    succeed(probe, Navigate(cell=Cell(*cell)), f"navigate to ({cell[0]},{cell[1]}) {what}")


def beside(probe: Probe, person: str, action: Action, tries: int = 3) -> tuple[int, list[CommandStatus]]:
    """Walk the robot to ``person``, then send ``action`` (a say or an ask); in real time
    the person may have walked on meanwhile, so a command failed out of earshot is tried
    again from where they are now, up to ``tries`` times. The event count before the last
    try, and its statuses."""
    for _ in range(tries):
        go(probe, probe.cell_of(person), f"to {person}")
        mark = len(probe.stream.events)
        statuses = probe.command(action)
        if not (probe.realtime and "earshot" in statuses[-1].reason):
            break
    return mark, statuses


def until_running(probe: Probe, command: str, what: str) -> None:
    """Step until ``command`` is running; fail unless it is within 20 ticks."""

    def running() -> bool:
        return CommandState.RUNNING in [s.state for s in probe.statuses_of(command)]

    if not probe.run_until(running, 20):
        raise CheckFailed(
            f"{what}: expected running within 20 ticks, got {shown(probe.statuses_of(command))}"
        )
