"""What the conformance checks stand on: a :class:`Probe` that talks to an engine (control
requests, streams of what it publishes, robot commands followed to their end), and how a
check reports (:class:`CheckResult` with its :class:`CheckOutcome`; a check raises
:class:`CheckFailed`, :class:`CheckSkipped` or :class:`NotApplicable`)."""

from __future__ import annotations

import enum
import threading
import uuid
from collections.abc import Callable
from dataclasses import dataclass, field

from protocol import (
    Action,
    AgentKind,
    ClockMode,
    CommandStatus,
    ControlReply,
    Encoding,
    EngineInfo,
    Event,
    GridCell,
    Heartbeat,
    Message,
    Pause,
    Reset,
    Resume,
    RobotCommand,
    State,
    Step,
    Truth,
    UnknownAction,
)

from ..bridge import Bridge
from ..errors import BridgeError
from ..pubsub import Publisher, Received

HEARTBEAT_SECONDS = 0.25
"""How often the kit beats while it drives a real-time engine's robot (as the brain does)."""
REALTIME_SLACK = 2.0
"""Real time: the kit waits for ``n`` ticks up to ``REALTIME_SLACK * n * tick_seconds`` plus its
timeout (the engine's clock, not the kit's, decides when a tick comes)."""


def kind_of(action: Action | UnknownAction) -> str:
    """A command's kind as sent (``navigate``, ...)."""
    return action.kind if isinstance(action, UnknownAction) else str(type(action).__struct_config__.tag)


class CheckOutcome(enum.Enum):
    """How a check ended."""

    PASSED = "pass"
    """It ran and the engine did what the protocol says."""
    SKIPPED = "skip"
    """It applies to this engine but could not run: what it needs was not there (a robot that
    acts, a free item, a reachable spot); the reason says what. ``--strict`` fails on it."""
    NOT_APPLICABLE = "n/a"
    """It does not apply to what the engine declares (the other clock mode, a capability it
    does not claim)."""
    FAILED = "FAIL"
    """The engine did not do what the protocol says."""


@dataclass(frozen=True)
class CheckResult:
    """One check: its name, its outcome, and what was expected and what came (or why it was
    skipped)."""

    name: str
    outcome: CheckOutcome
    detail: str = ""

    @property
    def passed(self) -> bool:
        """Whether the check ran and passed."""
        return self.outcome is CheckOutcome.PASSED

    @property
    def failed(self) -> bool:
        return self.outcome is CheckOutcome.FAILED

    def line(self) -> str:
        return f"{self.outcome.value:<4}  {self.name}" + (f": {self.detail}" if self.detail else "")


class CheckFailed(Exception):
    """Raised inside a check: expected this, got that."""


class CheckSkipped(Exception):
    """Raised inside a check that applies but cannot run: says what it needed and did not
    find."""


class NotApplicable(CheckSkipped):
    """Raised inside a check that does not apply to what the engine declares."""


@dataclass
class _Stream:
    """Everything the engine publishes, collected in arrival order."""

    states: list[State] = field(default_factory=list)
    events: list[Event] = field(default_factory=list)
    statuses: list[CommandStatus] = field(default_factory=list)
    truths: list[Truth] = field(default_factory=list)
    arrivals: list[tuple[str, int, int]] = field(default_factory=list)
    """``(state | event, episode, tick)`` of every state and event, in arrival order."""
    cond: threading.Condition = field(default_factory=threading.Condition)

    def add(self, bucket: list, item: object) -> None:
        with self.cond:
            bucket.append(item)
            if isinstance(item, (State, Event)):
                self.arrivals.append((type(item).__name__.lower(), item.episode, item.tick))
            self.cond.notify_all()

    def wait(self, predicate: Callable[[], bool], timeout: float) -> bool:
        with self.cond:
            return self.cond.wait_for(predicate, timeout)


class Probe:
    """What every check is given (``check_<name>(probe)``): the engine of ``bridge``'s world,
    what it has published, and what the checks before learnt of it (its info, the tick)."""

    def __init__(self, bridge: Bridge, timeout: float = 5.0) -> None:
        self.bridge = bridge
        self.timeout = timeout
        self.keys = bridge.keys
        self.stream = _Stream()
        self.info: EngineInfo | None = None
        self.episode = 0
        self.tick = 0
        self._ids = 0
        self._run = uuid.uuid4().hex[:6]
        """A command id prefix of this run: a real-time engine is not reset between runs, and
        may refuse an id it has seen (``conform<run>-<n>``)."""
        self._publishers: dict[tuple[str, Encoding | None], Publisher[Message]] = {}
        self.last = ControlReply(episode=0, tick=0, time=0.0)
        """The newest control reply."""
        self.silent = False
        """Real time: whether the kit holds its heartbeats (the heartbeat check does)."""
        self._beater: threading.Thread | None = None
        self._closing = threading.Event()
        # one subscriber for states, events and truth, so their arrival order is the wire's
        bridge.subscribe(f"{self.keys.prefix}/engine/*", self._on_engine)
        bridge.subscribe(self.keys.status(), self._on_status, expected=CommandStatus)

    def _on_engine(self, message: Message, received: Received) -> None:
        for key, kind, bucket in (
            (self.keys.state, State, self.stream.states),
            (self.keys.events, Event, self.stream.events),
            (self.keys.truth, Truth, self.stream.truths),
        ):
            if received.key == key and isinstance(message, kind):
                self.stream.add(bucket, message)

    def _on_status(self, status: CommandStatus, _: Received) -> None:
        self.stream.add(self.stream.statuses, status)

    # ----- helpers --------------------------------------------------------------------

    def control(self, request: Reset | Step | Pause | Resume) -> ControlReply:
        try:
            reply = self.bridge.query(self.keys.control, request, ControlReply, timeout=self.timeout)
        except BridgeError as err:
            raise CheckFailed(f"expected a control_reply to {request!r}, got: {err}") from None
        self.last = reply
        return reply

    @property
    def realtime(self) -> bool:
        """Whether the engine runs its own clock (the kit then waits for ticks instead of
        stepping them, and beats for its robot)."""
        return self.info is not None and self.info.clock is ClockMode.REALTIME

    def step(self, n: int) -> ControlReply:
        """Lock-step: ``step n``, the reply. Real time: wait for the engine's clock to pass ``n``
        more ticks (see :data:`REALTIME_SLACK`); a reply made of the newest state."""
        if not self.realtime:
            reply = self.control(Step(n=n))
            self.tick = reply.tick
            return reply
        assert self.info is not None
        start = self.latest().tick
        allowed = REALTIME_SLACK * n * self.info.tick_seconds + self.timeout
        if not self.stream.wait(lambda: self.latest().tick >= start + n, allowed):
            raise CheckFailed(
                f"real time: expected tick {start + n} within {allowed:.1f} s, "
                f"the newest is {self.latest().tick}"
            )
        state = self.latest()
        self.tick = state.tick
        return ControlReply(episode=state.episode, tick=state.tick, time=state.time, state=state)

    def keep_beating(self) -> None:
        """Real time: beat for the robot every :data:`HEARTBEAT_SECONDS` from now on (held
        while :attr:`silent`), so that the engine does not stop it while a check drives it."""
        if self._beater is not None or not self.realtime or self.robot is None:
            return
        robot = self.robot
        beats: Publisher[Message] = Publisher(self.bridge.session, self.keys.heartbeat(robot))

        def beat() -> None:
            seq = 0
            while not self._closing.wait(HEARTBEAT_SECONDS):
                if not self.silent:
                    beats.put(Heartbeat(robot=robot, seq=seq))
                    seq += 1
            beats.close()

        self._beater = threading.Thread(target=beat, name="conform heartbeats", daemon=True)
        self._beater.start()

    def close(self) -> None:
        """Stop beating (before the bridge closes)."""
        self._closing.set()
        if self._beater is not None:
            self._beater.join(timeout=2.0)

    @property
    def robot(self) -> str | None:
        assert self.info is not None
        robots = [a for a in self.info.scene.agents if a.kind is AgentKind.ROBOT]
        return robots[0].id if robots else None

    def send(self, action: Action | UnknownAction, encoding: Encoding | None = None) -> str:
        """Publish a command for the robot (in ``encoding``, default the bridge's); its id."""
        assert self.robot is not None
        self.keep_beating()
        self._ids += 1
        command = RobotCommand(id=f"conform{self._run}-{self._ids}", robot=self.robot, action=action)  # type: ignore[arg-type]
        key = self.keys.command(self.robot)
        publisher = self._publishers.get((key, encoding))
        if publisher is None:
            publisher = Publisher(self.bridge.session, key, encoding=encoding or self.bridge.encoding)
            self._publishers[(key, encoding)] = publisher
        if not publisher.wait_matched(self.timeout):
            raise CheckFailed(f"expected the engine to subscribe to '{key}', it did not")
        publisher.put(command)
        return command.id

    def statuses_of(self, command: str) -> list[CommandStatus]:
        """Every status published so far about ``command``, in arrival order."""
        with self.stream.cond:
            return [s for s in self.stream.statuses if s.command == command]

    def wait_status(self, command: str, timeout: float | None = None) -> list[CommandStatus]:
        """The statuses of ``command`` once it has one (or none after ``timeout``)."""
        self.stream.wait(
            lambda: bool(self.statuses_of(command)), self.timeout if timeout is None else timeout
        )
        return self.statuses_of(command)

    def run_until(self, done: Callable[[], bool], max_steps: int) -> bool:
        """Step one tick at a time until ``done()``; whether it came within ``max_steps`` (real
        time: within that many of the engine's ticks, :data:`REALTIME_SLACK`)."""
        if self.realtime:
            assert self.info is not None
            return self.stream.wait(done, REALTIME_SLACK * max_steps * self.info.tick_seconds + self.timeout)
        for _ in range(max_steps):
            if done():
                return True
            self.step(1)
        return done()

    def finish(self, command: str, what: str, max_steps: int = 400) -> list[CommandStatus]:
        """Step until ``command`` has a final status published; all its statuses."""

        def final() -> bool:
            got = self.statuses_of(command)
            return bool(got) and got[-1].state.final

        if self.realtime:
            if self.run_until(final, max_steps):
                ended = self.statuses_of(command)[-1].tick  # the state of its tick may come after it
                self.stream.wait(lambda: self.latest().tick >= ended, self.timeout)
                return self.statuses_of(command)
            raise CheckFailed(
                f"{what}: expected a final status within {max_steps} ticks of real time, got "
                f"{[s.state.value for s in self.statuses_of(command)]}"
            )
        for _ in range(max_steps):
            if final() or (
                any(s.command == command and s.state.final for s in self.last.statuses)
                and self.stream.wait(final, self.timeout)
            ):
                return self.statuses_of(command)
            self.step(1)
        if self.stream.wait(final, 0.2):
            return self.statuses_of(command)
        raise CheckFailed(
            f"{what}: expected a final status within {max_steps} ticks, got "
            f"{[s.state.value for s in self.statuses_of(command)]}"
        )

    def command(self, action: Action, *, max_steps: int = 400) -> list[CommandStatus]:
        """Send a command and step until it ends; every status it got."""
        command = self.send(action)
        self.wait_status(command)
        return self.finish(command, kind_of(action), max_steps)

    def latest(self) -> State:
        """The newest state: the last control reply's, else (and always in real time) the
        newest published."""
        if self.last.state is not None and not self.realtime:
            return self.last.state
        with self.stream.cond:
            if not self.stream.states:
                raise CheckFailed("expected a state by now, got none")
            return self.stream.states[-1]

    def cell_of(self, agent: str) -> GridCell:
        """Where ``agent`` stands in the newest state."""
        me = next((a for a in self.latest().agents if a.id == agent), None)
        if me is None:
            raise CheckFailed(f"expected agent '{agent}' in the state, it is missing")
        return (me.cell.col, me.cell.row)
