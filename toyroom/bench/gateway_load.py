"""The gateway under load with a stalled reader (``python -m toyroom.bench.gateway
--stalled-reader``; issue 64, item 5).

A ``toyroom gateway`` process; ``readers`` live readers, each a process of its own subscribed
to ``engine/state`` through it; one reader that subscribes and never reads (``stalled``);
and an engine, a WebSocket client putting states through the gateway as fast as it takes
them (full rate) for ``seconds``. Each state carries its number in ``tick``; the engine notes
when it sent each, the readers when each arrived (``time.monotonic``, one clock for every
process of the machine), so each live reader's lag is measured from the engine's send to its
receipt: p50, p99 and max, in milliseconds. The stalled reader must be dropped (its
liveliness token gone) and every live reader must get every state, in order, not dropped.
"""

from __future__ import annotations

import argparse
import json
import math
import queue
import subprocess
import sys
import tempfile
import threading
import time
import uuid
from collections.abc import Sequence
from contextlib import ExitStack
from pathlib import Path
from typing import Any

from websockets.exceptions import ConnectionClosed
from websockets.sync.client import ClientConnection, connect

PROBE = 1 << 40
"""The tick of the states that open the route to every reader (put until each has one)."""
END = PROBE + 1
"""The tick of the state that ends the run (each reader stops at it)."""


def _join(stack: ExitStack, url: str, role: str, name: str) -> ClientConnection:
    """A WebSocket client of the gateway, welcomed as ``role/name``, closed with ``stack``."""
    socket = stack.enter_context(connect(url, proxy=None, compression=None, max_size=None, close_timeout=1))
    socket.send(json.dumps({"op": "hello", "role": role, "name": name}))
    welcome = json.loads(socket.recv(timeout=30))
    if welcome.get("op") != "welcome":
        raise RuntimeError(f"the gateway refused {role}/{name}: {welcome}")
    return socket


def read(url: str, name: str) -> None:
    """A live reader (its own process): subscribe, note when each state arrives, and print
    ``ready``, ``routed`` (its first probe) and at the end one JSON line of receipts."""
    receipts: list[tuple[int, float]] = []
    closed, routed = None, False
    stack = ExitStack()
    socket = _join(stack, url, "viewer", name)
    socket.send(json.dumps({"op": "subscribe", "id": 1, "key": "engine/state"}))
    print("ready", flush=True)
    try:
        for text in socket:
            now = time.monotonic()
            tick = json.loads(text)["payload"]["tick"]
            if tick == END:
                break
            if tick == PROBE:
                if not routed:
                    routed = True
                    print("routed", flush=True)
                continue
            receipts.append((tick, now))
    except ConnectionClosed as err:
        closed = f"{err.rcvd.code} {err.rcvd.reason}" if err.rcvd is not None else "cut"
    stack.close()
    print(json.dumps({"receipts": receipts, "closed": closed}), flush=True)


class Reader:
    """A live reader's process and the lines it prints."""

    def __init__(self, url: str, name: str) -> None:
        self.name = name
        command = [sys.executable, "-m", "toyroom.bench.gateway_load", "--read", url, name]
        self.process = subprocess.Popen(command, stdout=subprocess.PIPE, text=True)
        self.lines: queue.Queue[str] = queue.Queue()
        threading.Thread(target=self._pump, daemon=True).start()

    def _pump(self) -> None:
        assert self.process.stdout is not None
        for line in self.process.stdout:
            self.lines.put(line.strip())
        self.lines.put("")  # it exited

    def expect(self, word: str, timeout: float) -> None:
        line = self.lines.get(timeout=timeout)
        if line != word:
            raise RuntimeError(f"reader {self.name}: expected {word!r}, got {line!r}")

    def result(self, timeout: float) -> dict[str, Any]:
        """Its receipts and how its connection ended (``None``: it ended the run itself)."""
        line = self.lines.get(timeout=timeout)
        self.process.wait(timeout=timeout)
        return dict(json.loads(line)) if line else {"receipts": [], "closed": "exited"}


class LoadEngine:
    """The engine: puts states through the gateway, noting when each was sent."""

    def __init__(self, stack: ExitStack, url: str, state: dict[str, Any]) -> None:
        self.socket = _join(stack, url, "engine", "loader")
        self.state = state
        self.sent: list[float] = []

    def put(self, tick: int) -> None:
        frame = json.dumps({"op": "put", "key": "engine/state", "payload": {**self.state, "tick": tick}})
        if tick < PROBE:
            self.sent.append(time.monotonic())
        self.socket.send(frame)

    def route(self, readers: list[Reader], timeout: float = 60.0) -> None:
        """Put probes until every reader has one (its subscription is in place)."""
        deadline = time.monotonic() + timeout
        for reader in readers:
            while True:
                self.put(PROBE)
                try:
                    reader.expect("routed", 0.05)
                    break
                except queue.Empty:
                    if time.monotonic() > deadline:
                        raise RuntimeError(f"reader {reader.name} got no state within {timeout} s") from None


def start_gateway(world: str, log: Path, extra: Sequence[str]) -> tuple[subprocess.Popen[bytes], str]:
    """``toyroom gateway`` on a free port with ``extra`` options, and its URL once it listens."""
    from bridge.processes import start_node, stop_node
    from bridge.session import SessionSettings

    from ..gateway import GATEWAY_READY, gateway_command

    process = start_node([*gateway_command(world, SessionSettings(), "ws://127.0.0.1:0"), *extra], log)
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline and process.poll() is None:
        if match := GATEWAY_READY.search(log.read_text(encoding="utf-8", errors="replace")):
            return process, match.group("url")
        time.sleep(0.05)
    stop_node(process)
    raise RuntimeError(f"the gateway did not start: {log.read_text()[-2000:]}")


def lag_summary(receipts: list[list[float]], sent: list[float]) -> dict[str, Any]:
    """One live reader's count, order and lag (ms from the engine's send to its receipt)."""
    ticks = [int(tick) for tick, _ in receipts]
    lags = sorted((at - sent[int(tick)]) * 1e3 for tick, at in receipts)
    at = lambda q: round(lags[min(len(lags) - 1, int(q * len(lags)))], 2) if lags else None  # noqa: E731
    return {
        "received": len(ticks),
        "every_state_in_order": ticks == list(range(len(sent))),
        "lag_ms": {"p50": at(0.5), "p99": at(0.99), "max": round(lags[-1], 2) if lags else None},
    }


def stalled_reader(
    state: dict[str, Any],
    readers: int = 4,
    seconds: float = 5.0,
    rate: float = 0.0,
    gateway_options: Sequence[str] = (),
    after: int | None = None,
) -> dict[str, Any]:
    """Run the load (see the module docstring); what it measured, and the gateway's log lines
    that dropped a client. With ``after``, the engine stops ``after`` states after the stalled
    reader is gone (``seconds`` is then the most it runs)."""
    from bridge import Bridge
    from bridge.processes import stop_node

    world = f"gwload{uuid.uuid4().hex[:6]}"
    with tempfile.TemporaryDirectory() as folder:
        log = Path(folder) / "gateway.log"
        gateway, url = start_gateway(world, log, gateway_options)
        try:
            with Bridge(world) as bridge:
                with ExitStack() as stack:
                    result = _load(stack, url, bridge, state, readers, (seconds, rate, after))
        finally:
            stop_node(gateway)
            result_log = log.read_text(encoding="utf-8", errors="replace")
    result["dropped"] = [line.split(": ", 1)[1] for line in result_log.splitlines() if " dropped: " in line]
    return result


def _load(
    stack: ExitStack,
    url: str,
    bridge: Any,
    state: dict[str, Any],
    readers: int,
    pace: tuple[float, float, int | None],
) -> dict[str, Any]:
    """The run itself, on a gateway at ``url`` and a Zenoh session of its world, the engine
    putting states as :func:`stalled_reader` says (``pace``: its seconds, rate and after)."""
    seconds, rate, after = pace
    viewers = bridge.presence("viewer")
    stalled = _join(stack, url, "viewer", "stalled")
    stalled.send(json.dumps({"op": "subscribe", "id": 1, "key": "engine/state"}))
    live = [Reader(url, f"live{i}") for i in range(readers)]
    for reader in live:
        reader.expect("ready", 60)
    engine = LoadEngine(stack, url, state)
    engine.route(live)
    gone: dict[str, float] = {}
    started = time.monotonic()

    def watch() -> None:
        if viewers.wait_gone("stalled", timeout=seconds + 60):
            gone.update(after_s=time.monotonic() - started, after_states=len(engine.sent))

    watcher = threading.Thread(target=watch, daemon=True)
    watcher.start()
    tick = 0
    while (now := time.monotonic()) - started < seconds:
        if after is not None and tick >= gone.get("after_states", math.inf) + after:
            break
        if rate and (due := started + tick / rate) > now:
            time.sleep(due - now)
        engine.put(tick)
        tick += 1
    took = time.monotonic() - started
    engine.put(END)
    results = {reader.name: reader.result(timeout=120) for reader in live}
    watcher.join(timeout=60)
    return {
        "readers": readers,
        "states": tick,
        "rate_hz": round(tick / took),
        "stalled": {**gone, "closed": _drain(stalled)},
        "live": {
            name: {**lag_summary(r["receipts"], engine.sent), "closed": r["closed"]}
            for name, r in results.items()
        },
    }


def _drain(socket: ClientConnection, timeout: float = 30.0) -> str:
    """Read what a stalled client was sent until its connection ends; how it ended."""
    deadline = time.monotonic() + timeout
    try:
        while time.monotonic() < deadline:
            socket.recv(timeout=max(deadline - time.monotonic(), 0.01))
    except ConnectionClosed as err:
        return f"{err.rcvd.code} {err.rcvd.reason}" if err.rcvd is not None else "cut (no close frame)"
    except TimeoutError:
        pass
    return "still open"


def summary_line(result: dict[str, Any]) -> str:
    """The run in one line."""
    lags = [r["lag_ms"] for r in result["live"].values()]
    worst = {q: max((x[q] for x in lags if x[q] is not None), default=None) for q in ("p50", "p99", "max")}
    whole = all(r["every_state_in_order"] and r["closed"] is None for r in result["live"].values())
    stalled = result["stalled"]
    return (
        f"gateway, {result['readers']} live readers and one stalled, {result['states']} states at "
        f"{result['rate_hz']} Hz: every live reader got every state: {'yes' if whole else 'NO'}; lag ms "
        f"p50 {worst['p50']}, p99 {worst['p99']}, max {worst['max']} (worst reader); the stalled reader "
        f"gone after {stalled.get('after_s', float('nan')):.2f} s ({stalled.get('after_states', '-')} "
        f"states), its close: {stalled['closed']}; dropped: {result['dropped']}"
    )


def main(argv: Sequence[str] | None = None) -> int:
    """The gateway's stalled-reader load test on ``argv``; the exit status."""
    parser = argparse.ArgumentParser(prog="python -m toyroom.bench.gateway --stalled-reader")
    parser.add_argument("--readers", type=int, default=4, help="live readers (default 4)")
    parser.add_argument(
        "--seconds", type=float, default=5.0, help="seconds the engine puts states (default 5)"
    )
    parser.add_argument("--rate", type=float, default=0.0, help="states per second (default 0: full rate)")
    parser.add_argument("--queue-frames", type=int, help="the gateway's --queue-frames (default: its own)")
    parser.add_argument("--ping", type=float, help="the gateway's --ping, seconds (default: its own)")
    parser.add_argument("--read", nargs=2, metavar=("URL", "NAME"), help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.read:
        read(*args.read)
        return 0
    from protocol import Encoding, encode
    from sim2d.engine import Engine as Sim

    state = json.loads(encode(Sim("paper-robot").state(), Encoding.JSON))
    options = [*(("--queue-frames", str(args.queue_frames)) if args.queue_frames else ())]
    options += [*(("--ping", str(args.ping)) if args.ping else ())]
    result = stalled_reader(state, args.readers, args.seconds, args.rate, options)
    print(json.dumps(result, indent=2))
    print(summary_line(result))
    return 0


if __name__ == "__main__":
    sys.exit(main())
