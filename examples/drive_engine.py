"""Drive an engine's clock from Python, as the brain does: handshake, reset, step, watch events.

A client on a real Zenoh session (loopback only, no multicast) asks the world's engine who it
is (:func:`bridge.handshake`: its :class:`protocol.EngineInfo`, the scene checked), prints
every event it publishes, resets it to its scenario and steps it with a
:class:`bridge.LockstepClient`, printing where each person stands after every step. This is
the API example of ``docs/usage.md``. Run an engine, then it::

    python examples/tiny_engine.py --world demo &        # or: toyroom sim --world demo
    python examples/drive_engine.py --world demo --steps 3
"""

from __future__ import annotations

import argparse
import sys

from bridge import Bridge, LockstepClient, handshake
from bridge.session import SessionSettings, add_network_args, settings_from_args
from protocol import State


def where(state: State) -> str:
    """Each agent's region in ``state``, in a line."""
    return ", ".join(f"{agent.id} in {agent.region}" for agent in state.agents)


def main(world: str, settings: SessionSettings, steps: int = 3, ticks: int = 1) -> None:
    """Reset the engine of ``world`` and step it ``steps`` times, ``ticks`` ticks a step."""
    with Bridge(world, settings) as bridge:
        info = handshake(bridge, client="my-analysis", timeout=10.0)  # EngineInfo, scene checked
        bridge.subscribe(bridge.keys.events, lambda event, _: print(f"  {event.actor} {event.kind}"))
        clock = LockstepClient(bridge, timeout=5.0)  # timeout=None to debug
        state: State = clock.reset(scenario=info.scenario, seed=1)
        print(f"engine '{info.engine}', scenario '{info.scenario}': tick {state.tick}: {where(state)}")
        for _ in range(steps):
            state = clock.step(ticks)
            print(f"tick {state.tick}: {where(state)}")


if __name__ == "__main__":
    sys.stdout.reconfigure(line_buffering=True)  # type: ignore[union-attr]  # a line as it is printed
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--steps", type=int, default=3, help="steps to take (default: 3)")
    parser.add_argument("--ticks", type=int, default=1, help="ticks a step (default: 1)")
    add_network_args(parser)
    args = parser.parse_args()
    main(args.world, settings_from_args(args), args.steps, args.ticks)
