"""Liveliness: a peer's token appears with it and disappears when it leaves: at once when it
closes, after its link's lease (0.8 s) when it is killed. The bounds below are generous on
purpose (a loaded machine schedules late); what they catch is a departure reported late by
seconds or never, and the latency itself is measured by `toyroom bench`."""

from __future__ import annotations

import subprocess
import sys
import textwrap
import time

from bridge import Bridge, PresenceEvent


def test_peer_disappearance_is_reported_within_one_second(world: str) -> None:
    with Bridge(world) as watcher_side:
        events: list[PresenceEvent] = []
        watcher = watcher_side.presence("engine", events.append)
        engine = Bridge(world)
        engine.token("engine", "sim2d")
        assert watcher.wait_alive("sim2d", timeout=5.0), "the engine's token never appeared"
        assert [p.role for p in watcher.alive] == ["engine"]

        closed_at = time.monotonic()
        engine.close()
        assert watcher.wait_gone("sim2d", timeout=5.0), "disappearance not reported within 5 s"
        gone = [e for e in events if not e.alive]
        assert len(gone) == 1 and gone[0].peer.name == "sim2d", f"expected one departure, got {gone}"
        assert gone[0].at - closed_at < 5.0, f"reported {gone[0].at - closed_at:.3f} s after closing"


def test_killed_peer_is_reported_after_its_lease(world: str) -> None:
    """A process killed with SIGKILL cannot withdraw its token: the link lease (0.8 s) does."""
    child = subprocess.Popen(
        [
            sys.executable,
            "-c",
            textwrap.dedent(
                f"""
                import time
                from bridge import Bridge
                bridge = Bridge({world!r})
                bridge.token("brain", "victim")
                print("up", flush=True)
                time.sleep(60)
                """
            ),
        ],
        stdout=subprocess.PIPE,
        text=True,
    )
    try:
        with Bridge(world) as watcher_side:
            watcher = watcher_side.presence()
            assert child.stdout is not None and child.stdout.readline().strip() == "up"
            assert watcher.wait_alive("victim", timeout=10.0)
            killed_at = time.monotonic()
            child.kill()
            assert watcher.wait_gone("victim", timeout=5.0), "a killed peer was not reported gone in 5 s"
            elapsed = time.monotonic() - killed_at
            assert elapsed < 5.0, f"killed peer reported gone after {elapsed:.2f} s (lease is 0.8 s)"
    finally:
        child.kill()
        child.wait(timeout=10)
