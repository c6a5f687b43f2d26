"""Stalls: the engine or the brain of ``toyroom run --scenario paper-robot`` stopped (SIGSTOP)
for 0.5, 1, 2 or 5 s at a random tick, then continued (SIGCONT). Each run must end one of two
ways, never a third: finished (exit 0) with one episode whose ticks run 0..n without a gap or
a reset, the very episode of a run without a stall (the same states and ``events.csv``, the
engine being deterministic in lock-step); or failed (non-zero exit) with one line saying what
went wrong, its folder marked ``FAILED``.

By default :data:`DEFAULT_STALLS` stalls (one of each length, of the engine or the brain at
random, at random ticks); ``TOYROOM_STALLS=20`` makes 20 in a row, ``TOYROOM_STALL_SEED=S``
replays a draw (every failure names its seed). Also here: an engine reset by another client
mid-run, which the run must not pass off as one episode.
"""

from __future__ import annotations

import json
import os
import random
import signal
import time
from dataclasses import dataclass
from pathlib import Path

import psutil
import pytest
from support import RunProcess

from bridge import Bridge, handshake
from protocol import ControlReply, Reset

pytestmark = pytest.mark.process

LENGTHS = (0.5, 1.0, 2.0, 5.0)
"""Seconds a node is stopped for: all under ``toyroom run``'s lease (8 s); under and well over
the short lease of ``--lease-ms 800``."""
DEFAULT_STALLS = 4
STALLS = int(os.environ.get("TOYROOM_STALLS", DEFAULT_STALLS))
SEED = int(os.environ.get("TOYROOM_STALL_SEED", random.SystemRandom().randrange(1_000_000)))
RUN_LIMIT_S = 120.0
"""Most seconds one run may take: about 4 s unloaded plus the stall; generous, for a loaded
2-core machine (a run that hangs is what must not pass)."""
LAST_TICK = 550
"""Stalls come at a tick of 10..LAST_TICK of paper-robot's 622, so the run is still on."""


@dataclass(frozen=True)
class Stall:
    node: str
    """``engine`` or ``brain``."""
    tick: int
    """Stopped once the run's trace holds this many states."""
    seconds: float
    short_lease: bool
    """Run with ``--lease-ms 800`` (links dropped by stalls over 0.8 s) instead of ``toyroom
    run``'s 8000 ms, under which every stall here must be waited for and the run carry on."""

    def __str__(self) -> str:
        lease = "--lease-ms 800" if self.short_lease else "the run's lease"
        return (
            f"{self.node} stopped {self.seconds:g} s once the trace held {self.tick} states, "
            f"{lease} (seed {SEED})"
        )

    def args(self) -> tuple[str, ...]:
        return ("--lease-ms", "800") if self.short_lease else ()


def planned(count: int, seed: int) -> list[Stall]:
    """``count`` stalls: every length in turn (shuffled), of a node drawn at random, at a
    random tick, with the run's lease or a short one in turn."""
    draw = random.Random(seed)
    kinds = [(LENGTHS[i % len(LENGTHS)], i % 2 == 1) for i in range(count)]
    draw.shuffle(kinds)
    return [
        Stall(draw.choice(("engine", "brain")), draw.randint(10, LAST_TICK), s, short) for s, short in kinds
    ]


class Run(RunProcess):
    """``toyroom run --scenario paper-robot --out OUT`` as a real process."""

    def __init__(self, out: Path, *args: str) -> None:
        self.out = out
        super().__init__("--scenario", "paper-robot", "--out", str(out), *args)
        self._read = 0
        self._states = 0

    def states_recorded(self) -> int:
        """How many states the run's trace holds so far (read on from the last look)."""
        staging = self.out.parent / f"{self.out.name}.running-{self.process.pid}" / "trace.jsonl"
        try:
            with staging.open("rb") as handle:
                handle.seek(self._read)
                chunk = handle.read()
        except OSError:
            return self._states
        complete = chunk[: chunk.rfind(b"\n") + 1]
        self._read += len(complete)
        self._states += complete.count(b'/engine/state"')
        return self._states

    def wait_for_tick(self, tick: int) -> None:
        """Wait (looking every 5 ms) until the trace holds ``tick`` states."""
        deadline = time.monotonic() + RUN_LIMIT_S
        while self.states_recorded() < tick:
            assert self.process.poll() is None, f"the run ended before tick {tick}:\n{self.output()}"
            assert time.monotonic() < deadline, f"no tick {tick} within {RUN_LIMIT_S} s:\n{self.output()}"
            time.sleep(0.005)

    def node(self, name: str) -> psutil.Process:
        found = self.nodes()
        if name not in found:
            raise AssertionError(f"no {name} process under toyroom run:\n{self.output()}")
        return found[name]

    def finish(self, timeout: float = RUN_LIMIT_S) -> int:
        return super().finish(timeout)


def state_payloads(trace: Path) -> list[dict]:
    """The states of a trace, in file order (their payloads: no world name in them)."""
    records = (json.loads(line) for line in trace.read_text().splitlines() if line.strip())
    return [r["payload"] for r in records if r["key"].endswith("/engine/state")]


@pytest.fixture(scope="module")
def baseline(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The folder of a run without a stall: what a run that carried on must equal."""
    out = tmp_path_factory.mktemp("baseline") / "out"
    run = Run(out)
    try:
        assert run.finish() == 0, f"the run without a stall failed:\n{run.output()}"
    finally:
        run.close()
    return out


def failed_folder(out: Path) -> Path:
    if (out / "FAILED").is_file():
        return out
    placed = sorted(out.parent.glob(f"{out.name}.failed-*"))
    assert placed, f"a failed run left no FAILED note in {out} or {out}.failed-*"
    return placed[-1]


def check_outcome(stall: Stall, run: Run, status: int, baseline: Path) -> str:
    """What the run did (``carried on`` or its failure line), having checked that it is one
    of the two allowed outcomes."""
    output = run.output()
    if status == 0:
        states = state_payloads(run.out / "trace.jsonl")
        ticks = [(s["episode"], s["tick"]) for s in states]
        expected = [(ticks[0][0], t) for t in range(len(ticks))] if ticks else []
        assert ticks == expected and states[-1]["done"], (
            f"{stall}: exit 0, so one episode's ticks 0..n were expected in trace.jsonl; "
            f"it holds {ticks[:3]}...{ticks[-3:]} ({len(ticks)} states, last done={states[-1]['done']})"
        )
        assert states == state_payloads(baseline / "trace.jsonl"), (
            f"{stall}: exit 0, so the very states of the run without a stall were expected "
            f"(lock-step is deterministic); {len(states)} states differ from the baseline's"
        )
        # the same rows; within a tick, the brain's rows and the engine's may come in either order
        got = sorted((run.out / "events.csv").read_text().splitlines())
        want = sorted((baseline / "events.csv").read_text().splitlines())
        assert got == want, (
            f"{stall}: exit 0, so the events.csv rows of the run without a stall were expected "
            f"({len(want)} lines); it has {len(got)}, of which these differ: "
            f"{sorted(set(got) ^ set(want))[:6]}"
        )
        return "carried on"
    lines = [line for line in output.splitlines() if line.strip()]
    last = lines[-1] if lines else ""
    assert last.startswith("toyroom run: ") and "partial outputs in" in last, (
        f"{stall}: exit {status}, so a last line saying why was expected; got {last!r}:\n{output}"
    )
    assert "results in" not in output, f"{stall}: a failed run claimed results:\n{output}"
    assert (failed_folder(run.out) / "FAILED").read_text().startswith("toyroom run did not finish: ")
    return last


@pytest.mark.sweep  # stalls at random ticks, a fault sweep: a minute of CPU (make test's budget)
@pytest.mark.timeout(60 + 60 * STALLS)
def test_a_stalled_engine_or_brain_never_merges_two_episodes(
    baseline: Path, tmp_path_factory: pytest.TempPathFactory
) -> None:
    outcomes: list[tuple[Stall, str]] = []
    started = time.monotonic()
    for stall in planned(STALLS, SEED):
        out = tmp_path_factory.mktemp("stall") / "out"
        run = Run(out, *stall.args())
        try:
            run.wait_for_tick(stall.tick)
            node = run.node(stall.node)
            node.send_signal(signal.SIGSTOP)
            try:
                time.sleep(stall.seconds)  # the fault itself: how long the node is stopped
            finally:
                node.send_signal(signal.SIGCONT)
            status = run.finish()
            outcomes.append((stall, check_outcome(stall, run, status, baseline)))
            assert stall.short_lease or outcomes[-1][1] == "carried on", (
                f"{stall}: a stall shorter than the run's lease (8 s) must be waited for; "
                f"the run failed instead: {outcomes[-1][1]}"
            )
            left = [p.pid for p in (node,) if p.is_running() and p.status() != psutil.STATUS_ZOMBIE]
            assert left == [], f"{stall}: the {stall.node} (pid {left}) outlived toyroom run"
        finally:
            run.close()
    carried = sum(1 for _, what in outcomes if what == "carried on")
    print(
        f"\n{len(outcomes)} stalls (seed {SEED}) in {time.monotonic() - started:.0f} s: "
        f"{carried} carried on, {len(outcomes) - carried} failed with a message"
    )
    for stall, what in outcomes:
        print(f"  {stall}: {what}")


def test_an_engine_reset_mid_run_by_another_client_fails_the_run(tmp_path: Path, world: str) -> None:
    """Another client resets the run's engine mid-episode: the brain steps on in the new
    episode, and the run must not pass the two off as one result."""
    out = tmp_path / "out"
    run = Run(out, "--world", world)
    try:
        run.wait_for_tick(100)
        with Bridge(world) as bridge:
            handshake(bridge, client="another", timeout=30.0)  # the engine is found
            reply = bridge.query(bridge.keys.control, Reset(scenario=None, seed=0), ControlReply)
        status = run.finish()
        output = run.output()
        lines = [line for line in output.splitlines() if line.strip()]
        assert status == 1, (
            f"exit 1 expected after the reset to episode {reply.episode}; got {status}:\n{output}"
        )
        assert "is not one episode's ticks 0..n: it holds episode 1 ticks 0-" in lines[-1], (
            f"a last line naming the two episodes expected; got {lines[-1]!r}"
        )
        assert f"then episode {reply.episode} ticks 0-" in lines[-1], lines[-1]
        assert (failed_folder(out) / "FAILED").is_file()
    finally:
        run.close()
