"""The lock-step client against a small engine made of the bridge's own parts."""

from __future__ import annotations

import threading
import time
from collections.abc import Iterator

import pytest

from bridge import Bridge, LockstepClient, Received, StepTimeout
from protocol import AgentState, Cell, ControlReply, Message, Pose, Reset, State, Step, Vec2


class CounterEngine:
    """A real engine on the wire, with a clock and one agent walking +x one cell a tick.

    ``delay`` seconds are spent in every step (to test timeouts); ``with_state`` chooses
    whether replies carry the state (engines may leave it out).
    """

    def __init__(self, world: str, *, delay: float = 0.0, with_state: bool = True) -> None:
        self.bridge = Bridge(world)
        self.delay = delay
        self.with_state = with_state
        self.episode = 0
        self.tick = 0
        self.publisher = self.bridge.publisher(self.bridge.keys.state)
        self.bridge.queryable(self.bridge.keys.control, self._control, expected=(Reset, Step))

    def state(self) -> State:
        agent = AgentState(
            id="walker",
            pose=Pose(self.tick + 0.5, 0.5),
            velocity=Vec2(1.0, 0.0),
            cell=Cell(self.tick, 0),
            region="hall",
        )
        return State(episode=self.episode, tick=self.tick, time=self.tick * 0.1, agents=(agent,), items=())

    def _control(self, request: Message | None, _: str) -> ControlReply:
        if isinstance(request, Reset):
            self.episode += 1
            self.tick = 0
            self.publisher.put(self.state())
        elif isinstance(request, Step):
            time.sleep(self.delay)
            for _ in range(request.n):
                self.tick += 1
                self.publisher.put(self.state())
        return ControlReply(
            episode=self.episode,
            tick=self.tick,
            time=self.tick * 0.1,
            state=self.state() if self.with_state else None,
        )

    def close(self) -> None:
        self.bridge.close()


@pytest.fixture
def engine(world: str) -> Iterator[CounterEngine]:
    engine = CounterEngine(world)
    yield engine
    engine.close()


def _client(world: str, timeout: float | None = 5.0) -> tuple[Bridge, LockstepClient]:
    bridge = Bridge(world)
    client = LockstepClient(bridge, timeout=timeout)
    deadline = time.monotonic() + 5.0
    while True:  # the engine's queryable may take a moment to be known
        try:
            client.reset(seed=1)
            return bridge, client
        except StepTimeout:
            if time.monotonic() > deadline:
                raise


@pytest.mark.parametrize("with_state", [True, False])
def test_step_advances_exactly_n_ticks(world: str, with_state: bool) -> None:
    engine = CounterEngine(world, with_state=with_state)
    bridge, client = _client(world)
    watcher = Bridge(world)
    seen: list[int] = []
    all_seen = threading.Event()

    def on_state(state: State, _: Received) -> None:
        seen.append(state.tick)
        if state.tick == 10:
            all_seen.set()

    watcher.subscribe(watcher.keys.state, on_state, expected=State)
    assert engine.publisher.wait_matched(5.0)
    time.sleep(0.3)  # both subscriptions must be known to the engine before stepping
    try:
        start = client.reset(seed=3)
        assert start.tick == 0 and start.episode == engine.episode
        assert client.step(3).tick == 3
        state = client.step(7)
        assert state.tick == 10 and state.agents[0].cell == Cell(10, 0)
        assert all_seen.wait(5.0), f"the watcher should see every tick, saw {seen}"
        assert seen[-10:] == list(range(1, 11)), f"ticks seen by a third party: {seen}"
    finally:
        watcher.close()
        bridge.close()
        engine.close()


def test_reset_starts_a_new_episode(engine: CounterEngine, world: str) -> None:
    bridge, client = _client(world)
    try:
        client.step(5)
        first = engine.episode
        state = client.reset(seed=2)
        assert (state.episode, state.tick) == (first + 1, 0)
    finally:
        bridge.close()


def test_unanswered_step_times_out_with_a_clear_error(world: str) -> None:
    engine = CounterEngine(world)
    bridge, client = _client(world, timeout=0.5)
    engine.delay = 3.0
    try:
        started = time.monotonic()
        with pytest.raises(StepTimeout) as caught:
            client.step(1)
        elapsed = time.monotonic() - started
        assert elapsed < 2.0, f"a 0.5 s timeout took {elapsed:.2f} s"
        text = str(caught.value)
        assert "Step(" in text and "timeout 0.5 s" in text and "timeout=None" in text, text
    finally:
        bridge.close()
        engine.close()


def test_disabled_timeout_waits_for_a_slow_engine(world: str) -> None:
    engine = CounterEngine(world)
    bridge, client = _client(world, timeout=None)
    engine.delay = 1.5
    try:
        started = time.monotonic()
        state = client.step(2)
        assert state.tick == 2 and time.monotonic() - started >= 1.4
    finally:
        bridge.close()
        engine.close()


def test_a_step_asked_again_is_carried_out_once(world: str) -> None:
    """A step the engine carries out but whose answer never reaches the client (here the client
    gives up before a slow engine answers; an engine paused past its lease carries out the
    step it was sent once continued, its answer lost with the link) is asked again with
    ``again()``, under its request id: the engine answers with that step's answer, not a second
    step. Before request ids the only way on was a new step: tick 2, and tick 1 never seen."""
    engine = CounterEngine(world)
    bridge, client = _client(world, timeout=0.5)
    engine.delay = 1.0
    try:
        with pytest.raises(StepTimeout):
            client.step(1)
        assert client.unanswered is not None and str(client.unanswered) == "step 1", client.unanswered
        deadline = time.monotonic() + 10
        while engine.tick < 1:  # the engine carries the step out after its delay
            assert time.monotonic() < deadline, "the engine never carried out the step"
            time.sleep(0.01)
        engine.delay = 0.0
        client.timeout = 5.0
        state = client.again()
        assert (state.tick, engine.tick) == (1, 1), (
            f"asked again, the step's own answer (tick 1, the engine at tick 1) was expected; got "
            f"tick {state.tick}, the engine at tick {engine.tick}"
        )
        assert client.unanswered is None, f"answered, nothing should be left to ask: {client.unanswered}"
        assert client.step(1).tick == 2, "a new step is a new request, carried out"
    finally:
        bridge.close()
        engine.close()
