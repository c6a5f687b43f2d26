"""A lock-step engine's reply path without the engine, for :mod:`toyroom.bench.lockstep`:
answers every ``Step`` on the world's control key through the bridge's typed queryable (in
Zenoh's callback thread, as sim2d's lock-step engine does) with one fixed reply carrying a
``paper-auto`` state. What a tick costs beyond this is the engine's own work.

    python -m toyroom.bench.typed_echo WORLD     (stops when stdin closes)
"""

from __future__ import annotations

import sys

from bridge import Bridge
from protocol import ControlReply, Message, Step
from sim2d.engine import Engine


def main(world: str) -> None:
    """Answer on ``world`` until stdin closes."""
    engine = Engine("paper-auto")
    for _ in range(50):
        engine.step()
    state = engine.state()
    reply = ControlReply(episode=state.episode, tick=state.tick, time=state.time, paused=False, state=state)

    def answer(request: Message | None, key: str) -> ControlReply:
        return reply

    with Bridge(world) as bridge:
        bridge.queryable(bridge.keys.control, answer, expected=(Step,), inline=True)
        print("ready", flush=True)
        sys.stdin.read()  # until the parent closes our stdin


if __name__ == "__main__":
    main(sys.argv[1])
