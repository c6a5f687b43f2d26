"""A client of the brain: print what each person most probably believes and wants, tick by tick.

It subscribes to the brain's ``brain/mind`` messages (:class:`protocol.Mind`) on a real Zenoh
session (loopback only, no multicast), and for each person prints the likeliest place of
every item, the likeliest want and the items the person more probably than not holds a
false belief about. It stops when the brain leaves the world, or at Ctrl-C. Run an engine
and a brain, and it beside them::

    python examples/watch_minds.py --world demo &
    toyroom run --world demo --scenario sally-anne --out out/demo    # sim2d and the brain
    # or: python examples/tiny_engine.py --world demo & python -m brain --world demo

A line reads ``tick 129 sally: marble@basket 1.00; wants out 1.00; false belief: marble`` (sally-anne).
"""

from __future__ import annotations

import argparse
import sys
import threading

from bridge import Bridge, PresenceEvent, Received, stop_on_signals, wait_for_stop
from bridge.session import SessionSettings, add_network_args, settings_from_args
from protocol import AgentMind, Mind, Prob


def likeliest(distribution: tuple[Prob, ...]) -> Prob | None:
    """The entry of ``distribution`` with the highest probability (``None``: empty)."""
    return max(distribution, key=lambda entry: entry.p, default=None)


def describe(person: AgentMind) -> str:
    """One person's mind in a line: beliefs, want, false beliefs."""
    beliefs = []
    for belief in person.beliefs:
        place = likeliest(belief.locations)
        beliefs.append(f"{belief.item}@{place.id} {place.p:.2f}" if place else f"{belief.item}@?")
    want = likeliest(person.preference)
    wants = f"wants {want.id} {want.p:.2f}" if want else "wants ?"
    false = f"; false belief: {', '.join(person.false_beliefs)}" if person.false_beliefs else ""
    return f"{', '.join(beliefs)}; {wants}{false}"


def main(world: str, settings: SessionSettings) -> None:
    """Print every mind published on ``world`` until its brain leaves (or SIGINT, SIGTERM)."""
    stop = threading.Event()

    def on_mind(mind: Mind, received: Received) -> None:
        for person in mind.agents:
            print(f"tick {mind.tick} {person.agent}: {describe(person)}")

    def on_brain(event: PresenceEvent) -> None:
        print(f"brain {event.peer.name} {'joined' if event.alive else 'left'}")
        if not event.alive:
            stop.set()

    with Bridge(world, settings) as bridge:
        bridge.subscribe(bridge.keys.mind, on_mind, expected=Mind)
        bridge.presence("brain", on_brain)
        print(f"watching the minds of world '{world}' (ready)")
        stop_on_signals(stop)
        wait_for_stop(stop)


if __name__ == "__main__":
    sys.stdout.reconfigure(line_buffering=True)  # type: ignore[union-attr]  # a line as it is printed
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    add_network_args(parser)
    args = parser.parse_args()
    main(args.world, settings_from_args(args))
