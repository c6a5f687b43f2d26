"""A replay up to a tick sends every message of the ticks up to it, in recorded order, and
none after: in real time a brain's mind of tick t is often logged after the engine's state
of t + 1, and a replay that stopped at the first later message lost it (the viewer then
waited for a mind that never came). Two real Zenoh sessions on loopback."""

from __future__ import annotations

import json
import threading
from pathlib import Path

from bridge import Bridge
from bridge.recording.readable import Recorded, Recording
from bridge.recording.replay import replay


def recording_of(world: str, order: list[tuple[str, int]]) -> Recording:
    """A recording of ``(kind, tick)`` messages (``state`` on the engine's key, ``mind`` on
    the brain's), in that order, 1 ms apart."""
    keys = {"state": f"toyroom/{world}/engine/state", "mind": f"toyroom/{world}/brain/mind"}
    records = tuple(
        Recorded(keys[kind], json.dumps({"tick": tick, "kind": kind}).encode(), log_time=1_000_000 * (i + 1))
        for i, (kind, tick) in enumerate(order)
    )
    return Recording(Path("made.mcap"), "mcap", records)


def test_a_replay_up_to_a_tick_keeps_a_mind_logged_after_the_next_state(
    bridges: tuple[Bridge, Bridge], world: str
) -> None:
    player, viewer = bridges
    order = [("state", 1), ("mind", 1), ("state", 2), ("state", 3), ("mind", 2), ("mind", 3), ("state", 4)]
    got: list[tuple[str, int]] = []
    last = threading.Event()

    def on_sample(sample: object) -> None:
        body = json.loads(bytes(sample.payload))  # type: ignore[attr-defined]
        got.append((body["kind"], body["tick"]))
        if (body["kind"], body["tick"]) == ("mind", 2):
            last.set()

    viewer.session.declare_subscriber(f"toyroom/{world}/**", on_sample)
    sent = replay(player, recording_of(world, order), speed=0, until_tick=2, wait_subscribers=10)
    assert last.wait(10), f"the mind of tick 2 (logged after the state of tick 3) never came; got {got}"
    want = [("state", 1), ("mind", 1), ("state", 2), ("mind", 2)]
    assert sent == len(want) and got == want, f"expected {want} ({len(want)} sent), got {got} ({sent} sent)"
