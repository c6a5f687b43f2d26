"""``toyroom bench [--quick] --out DIR``: the performance numbers, all measured in one run.

- ``zenoh_rtt_us``: median round trip of a raw zenoh-python ping-pong of a state-sized payload
  between two sessions on loopback (the floor for this language);
- ``lockstep_profile``: what a lock-step tick is made of: the same raw ping-pong between two
  processes (as the brain and the engine are); a raw query between two processes and the
  bridge's typed query answered with a fixed state and no engine (``typed_query_us``), both
  interleaved with the lock-step tick (``interleaved``: the ratios to the raw query per
  round of blocks, and the CPU each side spends per round trip; :mod:`.lockstep`);
  and the engine core's tick alone (``engine_step_vs_review``: against the review's commit,
  interleaved, :mod:`.engine_ab`; in a source checkout only);
- ``bridge_rtt_us``: the same through the bridge's typed messages (encode, decode);
- ``lockstep_tick_us`` / ``lockstep_ticks_per_s``: a lock-step client asks a sim2d engine
  process for one tick and gets its state back;
- ``gateway``: a query answered through ``toyroom gateway``, and a lock-step tick of the grid
  engine over Zenoh, through the gateway, and of the C# engine (:mod:`.gateway`; the engines'
  ticks need a source checkout);
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
  (:mod:`.scaling`);
- ``households_embodied``: the family's largest house (20 rooms, 10 items, 8 people), lapses
  on (``miss`` 0.2), with a robot that sees only what its own cell sees and, beside it, one
  that sees everything: peak memory, the first look's time, the tick's mean and p99
  (:mod:`.embodied`, in a process of its own; 200 ticks with ``--quick``).

It prints tables and writes ``DIR/bench.json``, ``DIR/perf.md`` and ``DIR/scaling.png``
(:mod:`.perfreport`: docs/performance.md).
"""

from __future__ import annotations

import json
import statistics
import subprocess
import tempfile
import threading
import time
import uuid
from pathlib import Path
from typing import Any

import zenoh

from bridge import Bridge
from bridge.processes import CHECKOUT
from bridge.session import SessionSettings, build_config
from protocol import State, encode
from sim2d.engine import Engine

from . import brainstep, embodied, engine_ab, gateway, lockstep, perfreport, scaling, summary


def ping_pong(send: Any, wait: threading.Event, payload: Any, rounds: int) -> list[float]:
    """Seconds of each of ``rounds`` round trips: ``send(payload)``, then ``wait`` set (a
    round trip not back within 2 s is left out)."""
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
    (:mod:`.lockstep`)."""
    world = f"bench{uuid.uuid4().hex[:6]}"
    echo = lockstep.start_echo("echo", world)
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
        lockstep.stop(echo)


def engine_step(rounds: int) -> list[float]:
    """Seconds of each of ``rounds`` ticks of the engine core on ``paper-auto`` in this
    process (no network)."""
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
with its, interleaved in this run (:mod:`.engine_ab`)."""


def engine_against_review() -> dict[str, Any] | None:
    """The engine's tick on ``paper-auto`` now and at :data:`REVIEW_COMMIT`, interleaved
    (``None``, said in one line, where there is no git checkout, as in an installed wheel,
    or that commit is missing, as in an exported tree)."""
    if not (CHECKOUT / ".git").exists():
        print(
            "engine against the review's commit: skipped (needs a source checkout: "
            f"{CHECKOUT} is not a git checkout)"
        )
        return None
    try:
        with tempfile.TemporaryDirectory(prefix="toyroom-ab-") as folder:
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
        timing: dict[str, Any] = evaluate(episodes, 1, Path(folder)).timing
    return {**timing, "episodes": episodes}


def main(quick: bool, out: Path) -> dict[str, Any]:
    """Every number (``quick``: fewer rounds, repeats and houses), printed as a table and
    written to ``out``: ``bench.json``, ``perf.md`` and ``scaling.png``."""
    numbers = measure(quick)
    out.mkdir(parents=True, exist_ok=True)
    (out / "bench.json").write_text(json.dumps(numbers, indent=2) + "\n")
    summary.show(numbers)
    perfreport.write(out / "bench.json")
    print(f"wrote {out / 'bench.json'}, {out / 'perf.md'} and {out / 'scaling.png'}")
    return numbers


def measure(quick: bool) -> dict[str, Any]:
    """Every number of ``bench.json`` (times in the units their names say)."""
    rounds = 300 if quick else 2000
    state = Engine("paper-robot").state()
    payload = encode(state)
    zenoh_times = zenoh_rtt(rounds, payload)
    bridge_times = bridge_rtt(rounds, state)
    pubsub_times = cross_process(rounds, payload)
    gone_times = presence_gone(5 if quick else 20)
    ticks = lockstep.measure(payload, blocks=10 if quick else 30, rounds=100 if quick else 200)
    engine_times = engine_step(rounds)
    engine_then = engine_against_review()
    through = gateway.main(rounds // 2, state)
    evaluation = eval_speed(2 if quick else 20)
    brain = brainstep.main(repeats=1 if quick else 5)
    scaled = scaling.main(quick)
    households_embodied = embodied.apart(quick)
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
        "gateway": through,
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
        "households_embodied": households_embodied,
    }
    return numbers
