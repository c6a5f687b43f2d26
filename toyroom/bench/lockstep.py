"""A lock-step tick against the raw query it is built on, interleaved in one run.

This machine's speed drifts by up to 2x over seconds, so a tick timed after the raw query
compares poorly with it (two ``toyroom bench`` runs gave 2.1 x and 3.3 x). Here a sim2d
engine process (``paper-auto``) and a raw zenoh-python echo process (:mod:`.echo`)
run side by side, and the client alternates blocks of raw queries (a state-sized payload
each way, answered in Zenoh's callback thread) with blocks of lock-step ticks (``Step``,
the engine's reply with the state, decoded): the ratio is taken per pair of neighbouring
blocks (median, with the 10th-90th percentile range over the pairs).

It also reads the CPU time each side spends per round trip (``/proc``; the client's is
this process's): the engine's against the raw echo's says what of a tick is the engine's
own work and what is Zenoh's.

    python -m toyroom.bench.lockstep [--blocks 30] [--rounds 200]
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
import uuid
from collections.abc import Callable, Mapping
from pathlib import Path
from typing import Any

import zenoh

from bridge import Bridge, LockstepClient, handshake
from bridge.session import SessionSettings, build_config
from protocol import ControlReply, Step, encode
from sim2d.engine import Engine


def cpu_seconds(pid: int) -> float:
    """User and system CPU seconds of process ``pid`` so far (its threads included)."""
    fields = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def timed_block(ask: Callable[[], object], rounds: int, pid: int) -> tuple[list[float], float, float]:
    """``rounds`` round trips: their wall seconds, and the CPU seconds the peer process
    ``pid`` and this one spent on them."""
    peer, own = cpu_seconds(pid), time.process_time()
    times = []
    for _ in range(rounds):
        start = time.perf_counter()
        ask()
        times.append(time.perf_counter() - start)
    return times, cpu_seconds(pid) - peer, time.process_time() - own


def _summary(samples: list[float]) -> float:
    return statistics.median(samples) * 1e6


def start_echo(name: str, world: str) -> subprocess.Popen[str]:
    """An echo peer (``echo``: :mod:`.echo`, or ``typed_echo``: :mod:`.typed_echo`) on
    ``world``, once ready."""
    echo = subprocess.Popen(
        [sys.executable, "-m", f"toyroom.bench.{name}", world],
        stdin=subprocess.PIPE,
        stdout=subprocess.PIPE,
        text=True,
    )
    assert echo.stdout is not None and echo.stdout.readline().strip() == "ready", f"{name} did not start"
    return echo


def stop(process: subprocess.Popen[Any]) -> None:
    """Stop a peer: an echo by closing its stdin, any other process by SIGTERM."""
    if process.stdin is not None:
        process.stdin.close()
    else:
        process.terminate()
    process.wait(timeout=10)


def measure(payload: bytes, blocks: int = 30, rounds: int = 200) -> dict[str, Any]:
    """The interleaved comparison (microseconds): ``tick_us``, ``query_us`` and
    ``typed_query_us`` (medians over every round trip), each ratio to the raw query with its
    range, and the CPU per round trip of each peer and of the client."""
    world = f"bench{uuid.uuid4().hex[:6]}"
    processes = [start_echo("echo", world + "-raw"), start_echo("typed_echo", world + "-typed")]
    engine = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "sim2d",
            "--world",
            world,
            "--scenario",
            "paper-auto",
            "--log-level",
            "WARNING",
        ],
        stdout=subprocess.DEVNULL,
    )
    processes.append(engine)  # type: ignore[arg-type]
    session = zenoh.open(build_config(world + "-raw", SessionSettings()))
    try:
        querier = session.declare_querier("bench/query")

        def query() -> None:
            for reply in querier.get(payload=payload):
                assert reply.ok is not None, "the echo refused a query"
                reply.ok.payload.to_bytes()
                return

        deadline = time.monotonic() + 10
        while time.monotonic() < deadline and not list(querier.get(payload=payload)):
            time.sleep(0.1)  # until the echo's session and ours have found each other
        with Bridge(world) as bridge, Bridge(world + "-typed") as typed:
            handshake(bridge, client="bench", timeout=30.0)
            clock = LockstepClient(bridge, timeout=10.0)
            clock.reset(scenario="paper-auto")
            kinds = {
                "query": (query, processes[0].pid),
                "typed_query": (
                    lambda: typed.query(typed.keys.control, Step(n=1), ControlReply),
                    processes[1].pid,
                ),
                "tick": (lambda: clock.step(1), engine.pid),
            }
            return _interleave(kinds, blocks, rounds)
    finally:
        session.close()
        for process in processes:
            stop(process)


def _interleave(
    kinds: Mapping[str, tuple[Callable[[], object], int]], blocks: int, rounds: int
) -> dict[str, Any]:
    """Blocks of each kind in turn (the order rotating), and each kind's ratio to ``query``
    per round of blocks."""
    names = list(kinds)
    for _ in range(50):  # warm up each
        for ask, _pid in kinds.values():
            ask()
    times: dict[str, list[float]] = {name: [] for name in names}
    peer_cpu, own_cpu = dict.fromkeys(names, 0.0), dict.fromkeys(names, 0.0)  # seconds in all
    ratios: dict[str, list[float]] = {name: [] for name in names if name != "query"}
    for block in range(blocks):
        medians = {}
        for name in names[block % len(names) :] + names[: block % len(names)]:
            ask, pid = kinds[name]
            block_times, peer, own = timed_block(ask, rounds, pid)
            times[name] += block_times
            peer_cpu[name] += peer
            own_cpu[name] += own
            medians[name] = statistics.median(block_times)
        for name in ratios:
            ratios[name].append(medians[name] / medians["query"])
    out: dict[str, Any] = {f"{name}_us": _summary(times[name]) for name in names}
    for name, values in ratios.items():
        values.sort()
        prefix = "" if name == "tick" else f"{name}_"
        out[f"{prefix}ratio"] = statistics.median(values)
        out[f"{prefix}ratio_lo"] = values[len(values) // 10]
        out[f"{prefix}ratio_hi"] = values[-1 - len(values) // 10]
    trips = blocks * rounds
    out["cpu_us_per_round_trip"] = {
        **{f"{name}_peer": peer_cpu[name] / trips * 1e6 for name in names},
        **{f"{name}_client": own_cpu[name] / trips * 1e6 for name in names},
    }
    return {**out, "blocks": blocks, "rounds_per_block": rounds}


def main() -> None:
    """Print the comparison as JSON."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--blocks", type=int, default=30)
    parser.add_argument("--rounds", type=int, default=200)
    args = parser.parse_args()
    payload = encode(Engine("paper-robot").state())
    print(json.dumps(measure(payload, args.blocks, args.rounds), indent=2))


if __name__ == "__main__":
    main()
