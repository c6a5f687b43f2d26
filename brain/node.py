"""The brain node: the inference on the wire.

It waits for the engine's handshake, builds its model from the scene it receives (never
from engine files), drives the engine's clock in lock-step one tick at a time, updates
every person's online estimate from each tick's state and events, publishes ``brain/mind``
every tick, and holds the liveliness token ``@alive/brain/<name>``.
"""

from __future__ import annotations

import logging
from collections.abc import Callable

from bridge import Bridge, LockstepClient, handshake
from protocol import Event, State

from .outputs import mind_message
from .settings import ModelSettings
from .tracker import MindTracker, Observer

log = logging.getLogger("toyroom.brain")

BRAIN_NAME = "toyroom-brain"


class BrainNode:
    """Runs the inference against whatever engine serves the bridge's world.

    Args:
        bridge: an open bridge on the world.
        settings: model parameters.
        observer: which person model to use.
        timeout: seconds each lock-step request may take (``None``: no limit).
        handshake_timeout: seconds to wait for an engine to answer.
    """

    def __init__(
        self,
        bridge: Bridge,
        *,
        settings: ModelSettings | None = None,
        observer: Observer = Observer.BTOM,
        timeout: float | None = 10.0,
        handshake_timeout: float | None = 30.0,
    ) -> None:
        self.bridge = bridge
        self.settings = settings or ModelSettings()
        self.observer = observer
        self.timeout = timeout
        self.handshake_timeout = handshake_timeout
        self._mind = bridge.publisher(bridge.keys.mind)
        bridge.token("brain", BRAIN_NAME)

    def run(
        self,
        scenario: str | None = None,
        seed: int = 0,
        *,
        max_ticks: int | None = None,
        on_tick: Callable[[State, tuple[Event, ...]], None] | None = None,
    ) -> tuple[str, MindTracker]:
        """Reset the engine, follow the episode to its end, return (scenario, tracker)."""
        first = handshake(self.bridge, client=BRAIN_NAME, role="brain", timeout=self.handshake_timeout)
        clock = LockstepClient(self.bridge, timeout=self.timeout)
        state = clock.reset(scenario=scenario or first.scenario or None, seed=seed)
        info = handshake(self.bridge, client=BRAIN_NAME, role="brain", timeout=self.handshake_timeout)
        log.info("engine '%s', scenario '%s', scene '%s'", info.engine, info.scenario, info.scene.name)
        tracker = MindTracker(info.scene, self.settings, self.observer)
        events = clock.last_reply.events if clock.last_reply is not None else ()
        self._tick(tracker, state, events, on_tick)
        while not state.done and (max_ticks is None or state.tick < max_ticks):
            state = clock.step(1)
            events = clock.last_reply.events if clock.last_reply is not None else ()
            self._tick(tracker, state, events, on_tick)
        clock.close()
        return info.scenario, tracker

    def _tick(
        self,
        tracker: MindTracker,
        state: State,
        events: tuple[Event, ...],
        on_tick: Callable[[State, tuple[Event, ...]], None] | None,
    ) -> None:
        tracker.observe(state, events)
        self._mind.put(mind_message(tracker, state))
        if on_tick is not None:
            on_tick(state, events)
