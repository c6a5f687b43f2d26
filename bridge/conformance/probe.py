"""What the conformance checks stand on: a :class:`Probe` that talks to an engine (control
requests, streams of what it publishes, robot commands followed to their end), and how a
check reports (:class:`CheckResult`, :class:`CheckFailed`)."""

from __future__ import annotations

import threading
from collections.abc import Callable
from dataclasses import dataclass, field

from protocol import (
    Action,
    AgentKind,
    CommandStatus,
    ControlReply,
    EngineInfo,
    Event,
    Reset,
    RobotCommand,
    State,
    Step,
    Truth,
)

from ..bridge import Bridge
from ..errors import BridgeError
from ..pubsub import Received


@dataclass(frozen=True)
class CheckResult:
    """One check: its name, whether it passed, and what was expected and what came."""

    name: str
    passed: bool
    detail: str = ""

    def line(self) -> str:
        mark = "pass" if self.passed else "FAIL"
        return f"{mark}  {self.name}" + (f": {self.detail}" if self.detail else "")


class CheckFailed(Exception):
    """Raised inside a check: expected this, got that."""


@dataclass
class _Stream:
    """Everything the engine publishes, collected in arrival order."""

    states: list[State] = field(default_factory=list)
    events: list[Event] = field(default_factory=list)
    statuses: list[CommandStatus] = field(default_factory=list)
    truths: list[Truth] = field(default_factory=list)
    cond: threading.Condition = field(default_factory=threading.Condition)

    def add(self, bucket: list, item: object) -> None:
        with self.cond:
            bucket.append(item)
            self.cond.notify_all()

    def wait(self, predicate: Callable[[], bool], timeout: float) -> bool:
        with self.cond:
            return self.cond.wait_for(predicate, timeout)


class Probe:
    """Runs the checks against the engine of ``bridge``'s world."""

    def __init__(self, bridge: Bridge, timeout: float = 5.0) -> None:
        self.bridge = bridge
        self.timeout = timeout
        self.keys = bridge.keys
        self.stream = _Stream()
        self.info: EngineInfo | None = None
        self.episode = 0
        self.tick = 0
        self._ids = 0
        bridge.subscribe(self.keys.state, lambda m, _: self.stream.add(self.stream.states, m), expected=State)
        bridge.subscribe(
            self.keys.events, lambda m, _: self.stream.add(self.stream.events, m), expected=Event
        )
        bridge.subscribe(self.keys.status(), self._on_status, expected=CommandStatus)
        bridge.subscribe(self.keys.truth, lambda m, _: self.stream.add(self.stream.truths, m), expected=Truth)

    def _on_status(self, status: CommandStatus, _: Received) -> None:
        self.stream.add(self.stream.statuses, status)

    # ----- helpers --------------------------------------------------------------------

    def control(self, request: Reset | Step) -> ControlReply:
        try:
            return self.bridge.query(self.keys.control, request, ControlReply, timeout=self.timeout)
        except BridgeError as err:
            raise CheckFailed(f"expected a control_reply to {request!r}, got: {err}") from None

    def step(self, n: int) -> ControlReply:
        reply = self.control(Step(n=n))
        self.tick = reply.tick
        return reply

    @property
    def robot(self) -> str | None:
        assert self.info is not None
        robots = [a for a in self.info.scene.agents if a.kind is AgentKind.ROBOT]
        return robots[0].id if robots else None

    def command(self, action: Action, *, max_steps: int = 400) -> list[CommandStatus]:
        """Send a command and step until it ends; every status it got."""
        assert self.robot is not None
        self._ids += 1
        command = RobotCommand(id=f"conform{self._ids}", robot=self.robot, action=action)
        publisher = self.bridge.publisher(self.keys.command(self.robot))
        if not publisher.wait_matched(self.timeout):
            raise CheckFailed(
                f"expected the engine to subscribe to '{self.keys.command(self.robot)}', it did not"
            )
        publisher.put(command)

        def mine() -> list[CommandStatus]:
            return [s for s in self.stream.statuses if s.command == command.id]

        self.stream.wait(lambda: bool(mine()), self.timeout)
        for _ in range(max_steps):
            got = mine()
            if got and got[-1].state.final:
                return got
            self.step(1)
            self.stream.wait(lambda: bool(mine()) and mine()[-1].state.final, 0.05)
        raise CheckFailed(
            f"{type(action).__name__.lower()}: expected a final status within {max_steps} ticks, got "
            f"{[s.state.value for s in mine()]}"
        )

    # ----- the checks -----------------------------------------------------------------
