"""The ``mind`` message: its per-person parts are reused while the tracker hands out the same
estimate, and the messages are those built afresh, to the byte."""

from __future__ import annotations

from brain.outputs.results import MindCache, mind_message
from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from protocol import Event, EventKind, State, encode
from tests.scenes import corridor_scene, corridor_state


def test_a_tick_without_a_step_reuses_the_estimate_and_its_message() -> None:
    tracker = MindTracker(corridor_scene(), ModelSettings())
    cache: MindCache = {}
    tracker.observe(corridor_state(0, 5), [])
    first = tracker.online("p")
    mind_message(tracker, corridor_state(0, 5), cache=cache)
    part = cache["p"][1]
    tracker.observe(corridor_state(1, 5), [])  # stands still: no step, nothing moved
    assert tracker.online("p") is first, "expected the same estimate while nothing changed"
    again = mind_message(tracker, corridor_state(1, 5), cache=cache)
    assert again.agents[0] is part, "expected the person's part of the message reused"
    take = Event(episode=1, tick=2, time=1.4, kind=EventKind.TAKE, actor="p", item="ball", location="B")
    tracker.observe(corridor_state(2, 8, holding=True), [take])
    assert tracker.online("p") is not first, "a step (and the ball taken) gives a new estimate"


def test_cached_messages_are_the_fresh_ones_to_the_byte() -> None:
    ticks: list[tuple[State, list[Event]]] = [
        (corridor_state(t, c), []) for t, c in enumerate((5, 5, 6, 7, 8, 8))
    ]
    take = Event(episode=1, tick=6, time=4.2, kind=EventKind.TAKE, actor="p", item="ball", location="B")
    ticks.append((corridor_state(6, 8, holding=True), [take]))
    for perception in ("omniscient", "embodied"):
        tracker = MindTracker(corridor_scene(), ModelSettings(perception=perception))
        afresh = MindTracker(corridor_scene(), ModelSettings(perception=perception))
        cache: MindCache = {}
        for state, events in ticks:
            tracker.observe(state, events)
            afresh.observe(state, events)
            afresh._online.clear()  # every estimate read again from the filters
            cached = encode(mind_message(tracker, state, cache=cache))
            fresh = encode(mind_message(afresh, state))
            assert cached == fresh, f"{perception}, tick {state.tick}: {cached!r} != {fresh!r}"
