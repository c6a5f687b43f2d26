"""`toyroom router`: clients on (what could be) several machines meet through it."""

from __future__ import annotations

import queue
import subprocess
import sys

from support import free_port, golden_examples

from bridge import Bridge, SessionSettings
from protocol import State


def test_clients_meet_through_the_router(world: str) -> None:
    endpoint = f"tcp/127.0.0.1:{free_port()}"
    router = subprocess.Popen(
        [sys.executable, "-m", "toyroom", "router", "--listen", endpoint],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    try:
        assert router.stdout is not None
        line = router.stdout.readline()
        assert f"listening on {endpoint}" in line, f"router said {line!r}, stderr: {router.stderr}"
        client = SessionSettings(mode="client", connect=(endpoint,))
        with Bridge(world, client) as engine, Bridge(world, client) as brain:
            inbox: queue.Queue = queue.Queue()
            brain.subscribe(brain.keys.state, lambda m, _: inbox.put(m), expected=State)
            publisher = engine.publisher(engine.keys.state)
            assert publisher.wait_matched(10.0), "the subscription never crossed the router"
            publisher.put(golden_examples()["state"])
            assert inbox.get(timeout=5.0).tick == 42
    finally:
        router.terminate()
        assert router.wait(timeout=10) == 0, "the router should exit cleanly on SIGTERM"
