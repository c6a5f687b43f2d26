"""The robot's command book: commands sent, and what the engine said about each."""

from __future__ import annotations

from dataclasses import dataclass, field

from protocol import Action, Cancel, CommandState, CommandStatus, RobotCommand


@dataclass
class CommandBook:
    """Numbers commands, queues them for sending, and keeps their latest status.

    Attributes:
        robot: the robot's id.
        outbox: commands made since the last :meth:`drain`, in order.
    """

    robot: str
    outbox: list[RobotCommand] = field(default_factory=list)
    sent: dict[str, RobotCommand] = field(default_factory=dict)
    statuses: dict[str, CommandStatus] = field(default_factory=dict)
    history: list[CommandStatus] = field(default_factory=list)
    resent: dict[str, str] = field(default_factory=dict)
    """A command sent again under a new id (:meth:`resend_in_flight`) -> that id: what is
    asked of the old id is answered by the new one."""
    _counter: int = 0

    def send(self, action: Action) -> str:
        """Make a command for ``action``; return its id."""
        self._counter += 1
        command = RobotCommand(id=f"c{self._counter}", robot=self.robot, action=action)
        self.outbox.append(command)
        self.sent[command.id] = command
        return command.id

    def number_after(self, earlier: CommandBook) -> None:
        """Number this book's commands on from ``earlier``'s (a link to an engine that came back:
        it remembers the ids it was sent and refuses one used again)."""
        self._counter = max(self._counter, earlier._counter)

    def resend_in_flight(self) -> list[str]:
        """Send every command in flight again, each under a new id (an engine that was lost
        and is back may never have had it, or may have lost its answers); a command whose
        cancel was in flight is taken as cancelled. The new ids, in order."""
        cancelled = {c.action.command for c in self.sent.values() if isinstance(c.action, Cancel)}
        again = []
        for command_id in self.in_flight():
            if command_id in cancelled:
                self.record(
                    CommandStatus(
                        command=command_id,
                        robot=self.robot,
                        state=CommandState.CANCELLED,
                        tick=0,
                        reason="engine lost",
                    )
                )
                continue
            self.resent[command_id] = self.send(self.sent[command_id].action)
            again.append(self.resent[command_id])
        return again

    def current(self, command_id: str) -> str:
        """The id ``command_id`` goes by now (itself unless it was sent again)."""
        while command_id in self.resent:
            command_id = self.resent[command_id]
        return command_id

    def cancel(self, command_id: str) -> None:
        """Ask the engine to cancel ``command_id`` if it has not ended."""
        if not self.final(command_id):
            self.send(Cancel(command=self.current(command_id)))

    def drain(self) -> list[RobotCommand]:
        """The commands to send now."""
        out, self.outbox = self.outbox, []
        return out

    def record(self, status: CommandStatus) -> None:
        """Take in a status from the engine (duplicates and stale ones are ignored)."""
        known = self.statuses.get(status.command)
        if known is not None and (known.state.final or known == status):
            return
        self.statuses[status.command] = status
        self.history.append(status)

    def status(self, command_id: str) -> CommandStatus | None:
        return self.statuses.get(self.current(command_id))

    def final(self, command_id: str) -> bool:
        status = self.status(command_id)
        return status is not None and status.state.final

    def answered(self, command_id: str) -> bool:
        """Whether the engine has accepted or failed the command (it has received it)."""
        return self.current(command_id) in self.statuses

    def in_flight(self) -> list[str]:
        """Commands sent that have not ended (by the id they go by now)."""
        return [
            c
            for c in self.sent
            if c not in self.resent and not self.final(c) and not isinstance(self.sent[c].action, Cancel)
        ]

    @staticmethod
    def succeeded(status: CommandStatus | None) -> bool:
        return status is not None and status.state is CommandState.SUCCEEDED
