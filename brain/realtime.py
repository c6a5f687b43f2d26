"""What the brain node needs of a real-time engine on the wire: the engine's events handed
out with the state they lead up to, and heartbeats that tell the engine the brain still
drives its robot."""

from __future__ import annotations

import queue
import time

from bridge import Bridge
from protocol import Event, Heartbeat, State


class EventFeed:
    """A real-time engine's events, handed out with the state they lead up to."""

    def __init__(self, bridge: Bridge) -> None:
        self.queue: queue.Queue[Event] = queue.Queue()
        self.pending: list[Event] = []
        self.subscriber = bridge.subscribe(bridge.keys.events, lambda m, _: self.queue.put(m), expected=Event)

    def up_to(self, state: State) -> tuple[Event, ...]:
        """The events of ``state``'s episode up to its tick, not handed out before."""
        while not self.queue.empty():
            self.pending.append(self.queue.get_nowait())
        now = tuple(e for e in self.pending if e.episode == state.episode and e.tick <= state.tick)
        self.pending = [e for e in self.pending if (e.episode, e.tick) > (state.episode, state.tick)]
        return now

    def clear(self) -> None:
        self.pending.clear()


class Heartbeats:
    """Tells a real-time engine, at most every 0.25 s, that the brain still drives its robot."""

    PERIOD = 0.25

    def __init__(self, bridge: Bridge, robot: str) -> None:
        self.bridge = bridge
        self.robot = robot
        self.seq = 0
        self.last = 0.0
        self.publisher = bridge.publisher(bridge.keys.heartbeat(robot)) if robot != "none" else None

    def beat(self) -> None:
        now = time.monotonic()
        if self.publisher is not None and now - self.last >= self.PERIOD:
            self.publisher.put(Heartbeat(robot=self.robot, seq=self.seq))
            self.seq += 1
            self.last = now
