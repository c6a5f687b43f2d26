"""The lock-step client: step the engine N ticks and get the resulting state.

Lock-step is for reproducible experiments: the engine advances only when asked. Every
request has a timeout (default 5 s) that raises :class:`~bridge.errors.StepTimeout` with
what was asked and what was last seen, instead of hanging; ``timeout=None`` disables it,
for stepping through an engine in a debugger.

Every reset and step goes out under a request id of its own (:mod:`bridge.queries`). One that
got no answer is kept (:attr:`LockstepClient.unanswered`), and :meth:`LockstepClient.again`
asks it again under the same id: an engine that carried it out while its answer could not
arrive (paused past its link's lease: continued, it still reads the step it was sent) answers
with that answer, one that never got it carries it out now. Either way it happens once.
"""

from __future__ import annotations

import itertools
import threading
import time
import uuid
from dataclasses import dataclass

from protocol import ControlReply, Message, Pause, Reset, Resume, State, Step

from .bridge import Bridge
from .errors import BridgeError, NoReply, RemoteError, StepTimeout
from .pubsub import Received, Subscriber


@dataclass(frozen=True)
class Unanswered:
    """A reset or step that got no answer (timed out, or its link went down)."""

    request: Reset | Step
    request_id: str
    """The id it went out under (:meth:`LockstepClient.again` asks under it again)."""
    sent_at: float
    """When it was first sent (``time.monotonic()`` seconds)."""

    @property
    def ticks(self) -> int:
        """How many ticks it asks for: a step's ``n``, 0 for a reset."""
        return self.request.n if isinstance(self.request, Step) else 0

    def __str__(self) -> str:
        if isinstance(self.request, Step):
            return f"step {self.request.n}"
        return f"reset to '{self.request.scenario}'" if self.request.scenario else "reset"


class LockstepClient:
    """Drives an engine's clock over ``engine/control`` and follows ``engine/state``.

    Args:
        bridge: an open bridge on the engine's world.
        timeout: seconds each request may take, ``None`` for no limit.
    """

    def __init__(self, bridge: Bridge, *, timeout: float | None = 5.0) -> None:
        self.bridge = bridge
        self.timeout = timeout
        self._cond = threading.Condition()
        self._latest: State | None = None
        self._ids = itertools.count(1)
        self._prefix = uuid.uuid4().hex[:12]
        self.unanswered: Unanswered | None = None
        """The last reset or step, while it has no answer (:meth:`again` asks it again)."""
        self.last_reply: ControlReply | None = None
        """The engine's reply to the last reset or step: its ``events`` list what happened."""
        self._subscriber: Subscriber[State] | None = bridge.subscribe(
            bridge.keys.state, self._on_state, expected=State
        )
        """Follows ``engine/state`` until the engine shows that its replies carry the state
        (then every tick would be decoded twice, once for nothing)."""

    def _on_state(self, state: State, _: Received) -> None:
        with self._cond:
            if self._latest is None or (state.episode, state.tick) >= (
                self._latest.episode,
                self._latest.tick,
            ):
                self._latest = state
            self._cond.notify_all()

    @property
    def latest(self) -> State | None:
        """The newest state seen (from replies or the ``engine/state`` subscription)."""
        with self._cond:
            return self._latest

    def _deadline(self) -> float | None:
        return None if self.timeout is None else time.monotonic() + self.timeout

    def _control(
        self, request: Message, deadline: float | None, request_id: str | None = None
    ) -> ControlReply:
        remaining = None if deadline is None else max(deadline - time.monotonic(), 0.001)
        try:
            return self.bridge.query(
                self.bridge.keys.control, request, ControlReply, timeout=remaining, request_id=request_id
            )
        except NoReply as err:
            raise StepTimeout(self._explain(request, str(err))) from None

    def _explain(self, request: Message, what: str) -> str:
        latest = self.latest
        seen = (
            f"last state: episode {latest.episode} tick {latest.tick}"
            if latest is not None
            else "no state seen yet"
        )
        limit = "no limit" if self.timeout is None else f"timeout {self.timeout:g} s"
        return (
            f"{request!r} on world '{self.bridge.world}' failed ({limit}): {what}; {seen}. "
            "Pass timeout=None to wait forever while debugging."
        )

    def _result(self, request: Message, reply: ControlReply, deadline: float | None) -> State:
        self.last_reply = reply
        if reply.state is not None:
            self._on_state(reply.state, Received(self.bridge.keys.state, self.bridge.encoding))
            if self._subscriber is not None:
                self._subscriber.close()
                self._subscriber = None
            return reply.state
        if self._subscriber is None:  # an engine that stopped sending states in replies
            self._subscriber = self.bridge.subscribe(self.bridge.keys.state, self._on_state, expected=State)
        target = (reply.episode, reply.tick)

        def arrived() -> bool:
            return self._latest is not None and (self._latest.episode, self._latest.tick) >= target

        with self._cond:
            remaining = None if deadline is None else max(deadline - time.monotonic(), 0.0)
            if not self._cond.wait_for(arrived, remaining):
                raise StepTimeout(
                    self._explain(
                        request,
                        f"the engine replied tick {reply.tick} but its state never arrived",
                    )
                )
            assert self._latest is not None
            return self._latest

    def _ask(self, asked: Unanswered) -> State:
        """Send a reset or step under its request id; it stays :attr:`unanswered` until its
        answer (or a refusal) arrives."""
        self.unanswered = asked
        deadline = self._deadline()
        try:
            reply = self._control(asked.request, deadline, asked.request_id)
        except RemoteError:
            self.unanswered = None  # refused: answered
            raise
        self.unanswered = None
        return self._result(asked.request, reply, deadline)

    def _new(self, request: Reset | Step) -> Unanswered:
        return Unanswered(request, f"{self._prefix}-{next(self._ids)}", time.monotonic())

    def reset(self, scenario: str | None = None, seed: int = 0) -> State:
        """Start a new episode and return its first state."""
        return self._ask(self._new(Reset(scenario=scenario, seed=seed)))

    def step(self, n: int = 1) -> State:
        """Advance exactly ``n`` ticks and return the state after the last one."""
        return self._ask(self._new(Step(n=n)))

    def again(self) -> State:
        """Ask the :attr:`unanswered` reset or step again, under its request id, and return its
        state: an engine that carried it out already (its answer lost with a link that went
        down) answers with that answer, one that never got it carries it out now. An engine
        that keeps no answers by request id (one not built on this bridge) carries it out a
        second time: the caller compares the state with the one it expects.

        Raises:
            BridgeError: nothing is unanswered.
            StepTimeout: no answer this time either.
        """
        if self.unanswered is None:
            raise BridgeError("no reset or step is unanswered: nothing to ask again")
        return self._ask(self.unanswered)

    def where(self) -> ControlReply:
        """Where a lock-step engine's clock is now (its episode, tick and state), changing
        nothing: a ``resume``, which a lock-step engine answers with its state and ignores
        (``protocol/README.md``). For a client that lost its link and must know whether the
        engine moved meanwhile; not for a real-time engine (it would resume a paused clock).
        """
        request = Resume()
        deadline = self._deadline()
        reply = self._control(request, deadline)
        if reply.state is not None:
            self._on_state(reply.state, Received(self.bridge.keys.state, self.bridge.encoding))
        return reply

    def pause(self) -> ControlReply:
        """Pause a real-time engine."""
        return self._control(Pause(), self._deadline())

    def resume(self) -> ControlReply:
        """Resume a paused real-time engine."""
        return self._control(Resume(), self._deadline())

    def close(self) -> None:
        """Stop following the state; safe to call twice."""
        if self._subscriber is not None:
            self._subscriber.close()
            self._subscriber = None

    def __enter__(self) -> LockstepClient:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
