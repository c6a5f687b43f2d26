"""The lock-step client: step the engine N ticks and get the resulting state.

Lock-step is for reproducible experiments: the engine advances only when asked. Every
request has a timeout (default 5 s) that raises :class:`~bridge.errors.StepTimeout` with
what was asked and what was last seen, instead of hanging; ``timeout=None`` disables it,
for stepping through an engine in a debugger.
"""

from __future__ import annotations

import threading
import time

from protocol import ControlReply, Message, Pause, Reset, Resume, State, Step

from .bridge import Bridge
from .errors import NoReply, StepTimeout
from .pubsub import Received, Subscriber


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

    def _control(self, request: Message, deadline: float | None) -> ControlReply:
        remaining = None if deadline is None else max(deadline - time.monotonic(), 0.001)
        try:
            return self.bridge.query(self.bridge.keys.control, request, ControlReply, timeout=remaining)
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

    def reset(self, scenario: str | None = None, seed: int = 0) -> State:
        """Start a new episode and return its first state."""
        request = Reset(scenario=scenario, seed=seed)
        deadline = self._deadline()
        return self._result(request, self._control(request, deadline), deadline)

    def step(self, n: int = 1) -> State:
        """Advance exactly ``n`` ticks and return the state after the last one."""
        request = Step(n=n)
        deadline = self._deadline()
        return self._result(request, self._control(request, deadline), deadline)

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
