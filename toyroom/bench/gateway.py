"""The gateway's cost, measured beside the Zenoh paths it stands in for (``toyroom bench``).

- ``query_rtt_us``: a query with a state-sized payload answered by a WebSocket client that
  serves the key through the gateway (Zenoh -> gateway -> WebSocket -> gateway -> Zenoh),
  beside ``lockstep_profile.zenoh_query_two_processes_us`` (the same query answered by a
  Zenoh process);
- ``lockstep_tick_us``: a lock-step tick (step 1, its state back) of the same engine, the
  Python grid engine (examples/grid_engine/), over Zenoh (``direct``) and through the
  gateway (``gateway``), and of the C# SDK's grid engine under Mono through the gateway
  (``csharp``, when Mono is installed), all three running at once and stepped in turn;
  ``ratio`` is gateway / direct, the target <= 2. The grid engines come from the source
  checkout (``examples/``, the C# SDK): from an installed package, ``lockstep_tick_us`` is
  empty, and says so in one line.

``python -m toyroom.bench.gateway --stalled-reader [--readers N] [--seconds S] [--rate HZ]``
measures the gateway under load instead, beside a reader that never reads: each live
reader's lag, and how the stalled one was dropped (:mod:`.gateway_load`; docs/performance.md).
"""

from __future__ import annotations

import json
import shutil
import statistics
import subprocess
import sys
import tempfile
import threading
import time
import uuid
from pathlib import Path
from typing import Any

from websockets.sync.client import connect

from bridge import Bridge, LockstepClient, handshake, query
from bridge.processes import CHECKOUT, GRID_ENGINE, stop_node
from bridge.session import SessionSettings
from protocol import State

from ..gateway import start_gateway

GRID = CHECKOUT / GRID_ENGINE


class BenchGateway:
    """``python -m toyroom.gateway`` on a free port (:func:`toyroom.gateway.start_gateway`),
    for one measurement."""

    def __init__(self, world: str) -> None:
        self.folder = tempfile.TemporaryDirectory()
        log = Path(self.folder.name) / "gateway.log"
        self.process, self.url = start_gateway(world, SessionSettings(), log)

    def close(self) -> None:
        stop_node(self.process)
        self.folder.cleanup()


def query_rtt(rounds: int, state: State) -> list[float]:
    """Queries answered by a WebSocket client through the gateway (the state echoed back)."""
    world = f"gwbench{uuid.uuid4().hex[:6]}"
    gateway = BenchGateway(world)
    ready = threading.Event()

    def client() -> None:
        with connect(gateway.url, proxy=None, compression=None) as socket:
            socket.send(json.dumps({"op": "hello", "role": "bench", "name": "echo"}))
            socket.recv()
            socket.send(json.dumps({"op": "serve", "id": 1, "key": "bench/echo"}))
            ready.set()
            for text in socket:
                frame = json.loads(text)
                if frame.get("op") == "query":
                    socket.send(json.dumps({"op": "reply", "qid": frame["qid"], "payload": frame["payload"]}))

    threading.Thread(target=client, daemon=True).start()
    try:
        ready.wait(30)
        with Bridge(world) as bridge:
            key = f"{bridge.keys.prefix}/bench/echo"
            time.sleep(0.5)  # the gateway's queryable reaches this session
            for _ in range(50):
                query(bridge.session, key, state, State, timeout=5)
            times = []
            for _ in range(rounds):
                start = time.perf_counter()
                query(bridge.session, key, state, State, timeout=5)
                times.append(time.perf_counter() - start)
            return times
    finally:
        gateway.close()


class Clocked:
    """An engine process on ``world`` and a lock-step clock of it, reset to paper-robot."""

    def __init__(self, world: str, command: list[str]) -> None:
        self.process = subprocess.Popen(command, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
        self.bridge = Bridge(world)
        handshake(self.bridge, client="bench", timeout=30.0)
        self.clock = LockstepClient(self.bridge, timeout=10.0)
        self.clock.reset(scenario="paper-robot")
        for _ in range(50):
            self.clock.step(1)
        self.times: list[float] = []

    def tick(self) -> None:
        start = time.perf_counter()
        self.clock.step(1)
        self.times.append(time.perf_counter() - start)

    def close(self) -> None:
        self.clock.close()
        self.bridge.close()
        self.process.terminate()
        self.process.wait(timeout=10)


def lockstep(rounds: int) -> dict[str, Any]:
    """The same grid engine over Zenoh and through the gateway, and the C# one, stepped in
    turn (one tick of each per round), so that all three see the same machine (microseconds
    per tick, median; none, said in one line, outside a source checkout)."""
    if not GRID.is_file():
        print(
            f"gateway: the engines' ticks: skipped (needs a source checkout: {GRID_ENGINE} is not installed)"
        )
        return {}
    grid = [sys.executable, str(GRID), "--scenario", "paper-robot"]
    gateways: list[BenchGateway] = []
    engines: dict[str, Clocked] = {}
    try:
        world = f"gwdirect{uuid.uuid4().hex[:6]}"
        engines["direct"] = Clocked(world, [*grid, "--world", world])
        world = f"gwgrid{uuid.uuid4().hex[:6]}"
        gateways.append(BenchGateway(world))
        engines["gateway"] = Clocked(world, [*grid, "--world", world, "--gateway", gateways[-1].url])
        if shutil.which("mcs") and shutil.which("mono"):
            from ..gateway import csharp

            world = f"gwcs{uuid.uuid4().hex[:6]}"
            gateways.append(BenchGateway(world))
            folder = Path(tempfile.mkdtemp())
            csharp.export_scenario("paper-robot", folder)
            engines["csharp"] = Clocked(world, csharp.engine_command(gateways[-1].url, folder))
        for _ in range(rounds):
            for engine in engines.values():
                engine.tick()
    finally:
        for engine in engines.values():
            engine.close()
        for gateway in gateways:
            gateway.close()
    numbers: dict[str, Any] = {name: statistics.median(e.times) * 1e6 for name, e in engines.items()}
    numbers["ratio"] = numbers["gateway"] / numbers["direct"]
    return numbers


def main(rounds: int, state: State) -> dict[str, Any]:
    """The query's round trip and the engines' ticks (microseconds, medians)."""
    return {
        "query_rtt_us": statistics.median(query_rtt(rounds, state)) * 1e6,
        "lockstep_tick_us": lockstep(rounds),
    }


if __name__ == "__main__":
    if sys.argv[1:2] == ["--stalled-reader"]:
        from .gateway_load import main as under_load

        sys.exit(under_load(sys.argv[2:]))
    from sim2d.engine import Engine

    print(
        json.dumps(
            main(int(sys.argv[1]) if len(sys.argv) > 1 else 500, Engine("paper-robot").state()), indent=2
        )
    )
