"""Every bundled scenario runs to its end in lock-step, the engine being a real process
driven over loopback Zenoh by a client made of ``protocol`` and ``bridge`` only."""

from __future__ import annotations

import threading

import pytest
from support import EngineProcess

from bridge import Bridge, LockstepClient, Received, handshake
from protocol import Event, EventKind, State

EXPECTED_LABELS = {
    "paper-1": ["0", "1", "2", "3", "4", "swapped", "5", "6", "7", "8"],
    "paper-2": ["0", "1", "2", "3", "4", "swapped", "5", "6", "7", "8", "9"],
    "paper-3": ["0", "1", "2", "3", "4", "swapped", "5", "6", "7", "8"],
    "paper-robot": ["0", "1", "2", "3", "4", "swapped", "5", "6"],
    "paper-robot-decline": ["0", "1", "2", "3", "4", "swapped", "5", "6"],
    "paper-tidy": ["0", "1", "2", "3", "4", "moved", "5", "6"],
    "paper-deceive": ["0", "1", "2", "3", "moved", "4"],
    "sally-anne": ["play", "basket", "out", "moved", "back"],
    "sally-anne-window": ["play", "basket", "out", "moved", "peeked", "back", "take", "play-again"],
}


class Recorder:
    """Collects every state and event the engine publishes."""

    def __init__(self, bridge: Bridge) -> None:
        self.states: list[State] = []
        self.events: list[Event] = []
        self.lock = threading.Condition()
        bridge.subscribe(bridge.keys.state, self._state, expected=State)
        bridge.subscribe(bridge.keys.events, self._event, expected=Event)

    def _state(self, state: State, _: Received) -> None:
        with self.lock:
            self.states.append(state)
            self.lock.notify_all()

    def wait_for(self, last: State, timeout: float = 10.0) -> None:
        """Wait until the subscription has caught up with ``last`` (the step reply's state)."""
        with self.lock:
            caught_up = self.lock.wait_for(
                lambda: any((s.episode, s.tick) == (last.episode, last.tick) for s in self.states[-5:]),
                timeout,
            )
        assert caught_up, f"state tick {last.tick} never arrived on the subscription"

    def _event(self, event: Event, _: Received) -> None:
        with self.lock:
            self.events.append(event)
            self.lock.notify_all()

    def labels(self, episode: int, expected: int, timeout: float = 10.0) -> list[str]:
        """The waypoint labels of ``episode``, once ``expected`` of them have arrived (events
        come on their own subscription, so they may trail the last state)."""

        def found() -> list[str]:
            return [
                e.label
                for e in self.events
                if e.kind is EventKind.WAYPOINT and e.episode == episode and e.label
            ]

        with self.lock:
            self.lock.wait_for(lambda: len(found()) >= expected, timeout)
            return found()


def run_to_end(client: LockstepClient, scenario: str, seed: int = 0, chunk: int = 25) -> State:
    state = client.reset(scenario=scenario, seed=seed)
    while not state.done:
        state = client.step(chunk)
        assert state.tick < 10_000, "the scenario never ended"
    return state


@pytest.mark.parametrize("scenario", sorted(EXPECTED_LABELS))
def test_scenario_runs_to_its_end(world: str, scenario: str) -> None:
    with EngineProcess(world, "--scenario", scenario), Bridge(world) as bridge:
        info = handshake(bridge, client="test", role="test", timeout=30.0)
        assert info.scenario == scenario and info.engine.startswith("sim2d")
        recorder = Recorder(bridge)
        client = LockstepClient(bridge, timeout=60.0)
        end = run_to_end(client, scenario)
        recorder.wait_for(end)
        # every tick of the episode was published, in order, and the last one is 'done'
        deadline_states = [s for s in recorder.states if s.episode == end.episode]
        ticks = [s.tick for s in deadline_states]
        assert ticks[-1] == end.tick and end.done
        assert ticks == sorted(ticks), "states arrived out of order"
        labels = recorder.labels(end.episode, len(EXPECTED_LABELS[scenario]))
        assert labels == EXPECTED_LABELS[scenario], f"{scenario}: waypoints {labels}"


def test_paper_1_world_at_step_6(world: str) -> None:
    """At A1's step 6 (back in S1), the ball lies in S1 and A2 holds the skate in P2."""
    with EngineProcess(world, "--scenario", "paper-1"), Bridge(world) as bridge:
        handshake(bridge, client="test", timeout=30.0)
        client = LockstepClient(bridge, timeout=60.0)
        client.reset(scenario="paper-1")
        step6 = None
        hits: list[Event] = []
        while step6 is None:  # the step's reply carries its events: no race with a subscription
            state = client.step(1)
            assert client.last_reply is not None
            hits = [e for e in client.last_reply.events if e.label == "6" and e.actor == "A1"]
            if hits:
                step6 = state
        assert step6 is not None and step6.tick == hits[0].tick
        items = {i.id: i for i in step6.items}
        agents = {a.id: a for a in step6.agents}
        assert (items["ball"].location, items["ball"].held_by) == ("S1", None), items["ball"]
        assert items["skate"].held_by == "A2" and agents["A2"].region == "P2", (items["skate"], agents["A2"])
        assert agents["A1"].region == "S1"


def test_same_seed_gives_identical_state_stream(world: str) -> None:
    from protocol import encode

    with EngineProcess(world, "--scenario", "paper-2"), Bridge(world) as bridge:
        handshake(bridge, client="test", timeout=30.0)
        client = LockstepClient(bridge, timeout=60.0)
        streams = []
        for _ in range(2):
            state = client.reset(scenario="paper-2", seed=5)
            stream = []
            while not state.done:
                state = client.step(1)
                stream.append(encode(state).replace(f'"episode":{state.episode}'.encode(), b""))
            streams.append(stream)
        assert len(streams[0]) == len(streams[1]) > 100
        assert streams[0] == streams[1], "the same scenario and seed gave different states"
