"""``toyroom bench [--quick] --out DIR``: the performance numbers, all measured in one run.

- ``zenoh_rtt_us``: median round trip of a raw zenoh-python ping-pong of a state-sized payload
  between two sessions on loopback (the floor for this language);
- ``lockstep_profile``: what a lock-step tick is made of: the same raw ping-pong between two
  processes (as the brain and the engine are); a raw query between two processes and the
  bridge's typed query answered with a fixed state and no engine (``typed_query_us``), both
  interleaved with the lock-step tick (``interleaved``: the ratios to the raw query per
  round of blocks, and the CPU each side spends per round trip; ``bench/lockstep_bench.py``);
  and the engine core's tick alone (``engine_step_vs_review``: against the review's commit,
  interleaved);
- ``bridge_rtt_us``: the same through the bridge's typed messages (encode, decode);
- ``lockstep_tick_us`` / ``lockstep_ticks_per_s``: a lock-step client asks a sim2d engine
  process for one tick and gets its state back;
- ``gateway``: a query answered through ``toyroom gateway``, and a lock-step tick of the grid
  engine over Zenoh, through the gateway, and of the C# engine (``bench/gateway_bench.py``);
- ``eval_seconds_per_episode``: ``toyroom eval``'s wall seconds per episode with its defaults
  (2 workers; 20 episodes, two batches of 10 as a long sweep runs them, 2 with ``--quick``),
  ``eval_timing`` how they split into runs;
- ``brain_step_us`` (median, p99): the online update per person per step, paper map, with
  point beliefs (``graded.brain_step_us``: with the graded default);
- ``planner_cold_s``: the planner on the paper map with an empty cache (point; ``graded.``
  the same for the default);
- ``scaling``: the brain on a family of generated houses from 4 rooms and 2 items to 10 (12)
  rooms and 6 items, exact or factored as it runs by default, with ``tv_vs_exact`` wherever
  the exact model fits; ``paper_tv_vs_exact`` the same on the paper map's scenarios
  (``bench/scaling.py``).

It prints tables and writes ``DIR/bench.json``, ``DIR/perf.md`` and ``DIR/scaling.png``
(``bench/perfreport.py``: docs/performance.md).
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import tempfile
import threading
import time
import uuid
from pathlib import Path
from typing import Any

import zenoh
from rich.console import Console
from rich.table import Table

sys.path.insert(0, str(Path(__file__).parent))

import brain_bench  # noqa: E402
import engine_ab  # noqa: E402
import gateway_bench  # noqa: E402
import lockstep_bench  # noqa: E402
import perfreport  # noqa: E402
import scaling  # noqa: E402

from bridge import Bridge  # noqa: E402
from bridge.session import SessionSettings, build_config  # noqa: E402
from protocol import State, encode  # noqa: E402


def percentile(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(q * (len(ordered) - 1)))]


def ping_pong(send: Any, wait: threading.Event, payload: bytes, rounds: int) -> list[float]:
    times = []
    for _ in range(rounds):
        wait.clear()
        start = time.perf_counter()
        send(payload)
        if not wait.wait(2.0):
            continue
        times.append(time.perf_counter() - start)
    return times


def zenoh_rtt(rounds: int, payload: bytes) -> list[float]:
    """Two raw sessions: ping -> pong -> ping, plain bytes."""
    world = f"bench{uuid.uuid4().hex[:6]}"
    a = zenoh.open(build_config(world, SessionSettings()))
    b = zenoh.open(build_config(world, SessionSettings(listen=("tcp/127.0.0.1:0",))))
    try:
        back = threading.Event()
        pong = b.declare_publisher("bench/pong")
        b.declare_subscriber("bench/ping", lambda s: pong.put(s.payload))
        a.declare_subscriber("bench/pong", lambda s: back.set())
        ping = a.declare_publisher("bench/ping")
        time.sleep(0.5)
        ping_pong(ping.put, back, payload, 50)  # warm up
        return ping_pong(ping.put, back, payload, rounds)
    finally:
        a.close()
        b.close()


def cross_process(rounds: int, payload: bytes) -> list[float]:
    """Raw zenoh-python publication ping-pong with an echo peer in another process (as the
    brain and the engine are); the raw query is measured interleaved with the lock-step tick
    (:mod:`lockstep_bench`)."""
    world = f"bench{uuid.uuid4().hex[:6]}"
    echo = lockstep_bench.start_echo("echo.py", world)
    session = zenoh.open(build_config(world, SessionSettings()))
    try:
        back = threading.Event()
        session.declare_subscriber("bench/pong", lambda s: back.set())
        ping = session.declare_publisher("bench/ping")
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline and not ping_pong(ping.put, back, payload, 1):
            time.sleep(0.1)  # until the two sessions have found each other
        ping_pong(ping.put, back, payload, 50)
        return ping_pong(ping.put, back, payload, rounds)
    finally:
        session.close()
        lockstep_bench.stop(echo)


def engine_step(rounds: int) -> list[float]:
    """The engine core's tick on ``paper-auto`` in this process (no network)."""
    from sim2d.engine import Engine

    engine = Engine("paper-auto")
    for _ in range(50):
        engine.step()
    times = []
    for _ in range(rounds):
        start = time.perf_counter()
        engine.step()
        times.append(time.perf_counter() - start)
    return times


REVIEW_COMMIT = "83c38ee"
"""The commit the review measured (``../shared/REVIEW.md``): the engine's tick is compared
with its, interleaved in this run (``bench/engine_ab.py``)."""


def engine_against_review() -> dict[str, Any] | None:
    """The engine's tick on ``paper-auto`` now and at :data:`REVIEW_COMMIT`, interleaved
    (``None`` where git or that commit is missing, as in an exported tree)."""
    try:
        with tempfile.TemporaryDirectory(prefix="toyroom-ab-") as folder:
            from sim2d.engine import Engine

            then = engine_ab.other_engine(REVIEW_COMMIT, Path(folder))
            return {"commit": REVIEW_COMMIT, **engine_ab.compare(then, Engine, "paper-auto")}
    except (OSError, subprocess.CalledProcessError) as err:
        print(f"engine against the review's commit: skipped ({err})")
        return None


def bridge_rtt(rounds: int, state: State) -> list[float]:
    """The same through typed messages: encode, publish, decode, and back."""
    world = f"bench{uuid.uuid4().hex[:6]}"
    with Bridge(world) as a, Bridge(world) as b:
        back = threading.Event()
        pong = b.publisher(f"{b.keys.prefix}/bench/pong")
        b.subscribe(f"{b.keys.prefix}/bench/ping", lambda m, _: pong.put(m), expected=State)
        a.subscribe(f"{a.keys.prefix}/bench/pong", lambda m, _: back.set(), expected=State)
        ping = a.publisher(f"{a.keys.prefix}/bench/ping")
        assert ping.wait_matched(5.0) and pong.wait_matched(5.0)
        ping_pong(ping.put, back, state, 50)
        return ping_pong(ping.put, back, state, rounds)


def presence_gone(rounds: int) -> list[float]:
    """Seconds from a peer closing its session to its departure being reported (liveliness):
    what tests/bridge/test_presence.py checks only with a generous bound."""
    world = f"bench{uuid.uuid4().hex[:6]}"
    times = []
    with Bridge(world) as watching:
        watcher = watching.presence("engine")
        for index in range(rounds):
            peer = Bridge(world)
            peer.token("engine", f"p{index}")
            assert watcher.wait_alive(f"p{index}", timeout=10.0), "a peer's token never appeared"
            closed = time.monotonic()
            peer.close()
            assert watcher.wait_gone(f"p{index}", timeout=10.0), "a closed peer was never reported gone"
            times.append(time.monotonic() - closed)
    return times


def eval_speed(episodes: int) -> dict[str, Any]:
    """``toyroom eval``'s timing on ``episodes`` episodes with its defaults (2 workers): the
    target is 500 episodes in 10 minutes, 1.2 s per episode."""
    from toyroom.evaluation.episodes import evaluate

    with tempfile.TemporaryDirectory() as folder:
        timing: dict[str, Any] = evaluate(episodes, 1, Path(folder))["timing"]
    return {**timing, "episodes": episodes}


def main(quick: bool, out: Path) -> dict[str, Any]:
    rounds = 300 if quick else 2000
    from sim2d.engine import Engine  # only to make a state of the paper map's size

    state = Engine("paper-robot").state()
    payload = encode(state)
    zenoh_times = zenoh_rtt(rounds, payload)
    bridge_times = bridge_rtt(rounds, state)
    pubsub_times = cross_process(rounds, payload)
    gone_times = presence_gone(5 if quick else 20)
    ticks = lockstep_bench.measure(payload, blocks=10 if quick else 30, rounds=100 if quick else 200)
    engine_times = engine_step(rounds)
    engine_then = engine_against_review()
    gateway = gateway_bench.main(rounds // 2, state)
    evaluation = eval_speed(2 if quick else 20)
    brain = brain_bench.main(repeats=1 if quick else 5)
    scaled = scaling.main(quick)
    numbers: dict[str, Any] = {
        "quick": quick,
        "payload_bytes": len(payload),
        "zenoh_rtt_us": statistics.median(zenoh_times) * 1e6,
        "bridge_rtt_us": statistics.median(bridge_times) * 1e6,
        "lockstep_tick_us": ticks["tick_us"],
        "presence_gone_ms": {
            "median": statistics.median(gone_times) * 1e3,
            "max": max(gone_times) * 1e3,
        },
        "lockstep_ticks_per_s": 1e6 / ticks["tick_us"],
        "lockstep_profile": {
            "zenoh_rtt_two_processes_us": statistics.median(pubsub_times) * 1e6,
            "zenoh_query_two_processes_us": ticks["query_us"],
            "typed_query_us": ticks["typed_query_us"],
            "interleaved": {k: v for k, v in ticks.items() if not k.endswith("_us")},
            "engine_step_us": statistics.median(engine_times) * 1e6,
            "engine_step_vs_review": engine_then,
        },
        "gateway": gateway,
        "eval_seconds_per_episode": evaluation["seconds_per_episode"],
        "eval_timing": evaluation,
        "brain_step_us": {"median": brain["brain_step_us_median"], "p99": brain["brain_step_us_p99"]},
        "planner_cold_s": brain["planner_cold_s"],
        "graded": {
            "brain_step_us": {
                "median": brain["graded_brain_step_us_median"],
                "p99": brain["graded_brain_step_us_p99"],
            },
            "planner_cold_s": brain["graded_planner_cold_s"],
        },
        "scaling": scaled["scaling"],
        "paper_tv_vs_exact": scaled["paper_tv_vs_exact"],
    }
    out.mkdir(parents=True, exist_ok=True)
    (out / "bench.json").write_text(json.dumps(numbers, indent=2) + "\n")
    table = Table(title=f"toyroom bench{' --quick' if quick else ''} (state payload {len(payload)} bytes)")
    table.add_column("measure")
    table.add_column("value", justify="right")
    table.add_column("target", justify="right")
    table.add_row("zenoh_rtt_us (raw, median)", f"{numbers['zenoh_rtt_us']:.0f}", "")
    table.add_row("bridge_rtt_us (typed, median)", f"{numbers['bridge_rtt_us']:.0f}", "")
    profile = numbers["lockstep_profile"]
    mixed = profile["interleaved"]
    table.add_row(
        "lockstep_tick_us (median)",
        f"{numbers['lockstep_tick_us']:.0f}",
        f"<= 1.5 x raw query: {mixed['ratio']:.2f} x [{mixed['ratio_lo']:.2f}, {mixed['ratio_hi']:.2f}]",
    )
    table.add_row("lockstep_ticks_per_s", f"{numbers['lockstep_ticks_per_s']:.0f}", "")
    gone = numbers["presence_gone_ms"]
    table.add_row(
        "presence_gone_ms (closed peer, median / max)", f"{gone['median']:.0f} / {gone['max']:.0f}", "< 1000"
    )
    table.add_row("  raw ping-pong, two processes", f"{profile['zenoh_rtt_two_processes_us']:.0f}", "")
    table.add_row(
        "  raw query, two processes (interleaved)", f"{profile['zenoh_query_two_processes_us']:.0f}", ""
    )
    table.add_row(
        "  typed query, fixed state, no engine (interleaved)",
        f"{profile['typed_query_us']:.0f}",
        f"{mixed['typed_query_ratio']:.2f} x raw [{mixed['typed_query_ratio_lo']:.2f}, "
        f"{mixed['typed_query_ratio_hi']:.2f}]",
    )
    low, high = perfreport.REVIEW_ENGINE_STEP_US
    step = f"{profile['engine_step_us']:.0f}"
    table.add_row("  engine tick alone (paper-auto)", step, f"half of {low}-{high}")
    if engine_then is not None:
        table.add_row(
            f"  the same against {REVIEW_COMMIT} (interleaved, CPU time)",
            f"{engine_then['now_us']:.0f} / {engine_then['then_us']:.0f}",
            f"<= 0.5 x: {engine_then['ratio']:.2f} x",
        )
    ticks = gateway["lockstep_tick_us"]
    table.add_row("gateway: query answered over WebSocket", f"{gateway['query_rtt_us']:.0f}", "")
    table.add_row("grid engine tick, Zenoh", f"{ticks['direct']:.0f}", "")
    table.add_row(
        "grid engine tick, through the gateway",
        f"{ticks['gateway']:.0f}",
        f"<= {2 * ticks['direct']:.0f} (2 x)",
    )
    if "csharp" in ticks:
        table.add_row("C# grid engine tick (Mono), gateway", f"{ticks['csharp']:.0f}", "")
    table.add_row(
        f"eval_seconds_per_episode ({evaluation['episodes']} episodes, {evaluation['workers']} workers)",
        f"{evaluation['seconds_per_episode']:.2f}",
        "<= 1.2 (500 in 10 min)",
    )
    table.add_row(
        "point beliefs: brain_step_us median / p99",
        f"{brain['brain_step_us_median']:.0f} / {brain['brain_step_us_p99']:.0f}",
        "<= 1000",
    )
    table.add_row("point beliefs: planner_cold_s", f"{numbers['planner_cold_s']:.3f}", "<= 0.5")
    graded = numbers["graded"]
    table.add_row(
        "graded beliefs (the default): brain_step_us median / p99",
        f"{graded['brain_step_us']['median']:.0f} / {graded['brain_step_us']['p99']:.0f}",
        "<= 1000",
    )
    table.add_row("graded beliefs (the default): planner_cold_s", f"{graded['planner_cold_s']:.3f}", "<= 2")
    Console().print(table)
    perfreport.write(out / "bench.json")
    print(f"wrote {out / 'bench.json'}, {out / 'perf.md'} and {out / 'scaling.png'}")
    return numbers


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description="toyroom's performance numbers, measured in one run.")
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--out", type=Path, default=Path(tempfile.gettempdir()) / "toyroom-bench")
    arguments = parser.parse_args()
    main(arguments.quick, arguments.out)
