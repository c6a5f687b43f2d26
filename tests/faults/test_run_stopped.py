"""``toyroom run`` stopped from outside: SIGTERM or SIGINT to it, or its engine killed.

Each test runs ``toyroom run`` as a real process (engine and brain processes under it) on a
long episode (paper-2 with a 600-tick first step), acts once the run's trace shows the
moment it wants, and checks what a user finds: no process left, a meaningful exit status,
and a results folder that is either whole or marked ``FAILED`` with the ``toyroom infer``
command that recovers the rest (which is run to see that it does)."""

from __future__ import annotations

import csv
import json
import os
import shlex
import signal
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import psutil
import pytest
from support import RunProcess, long_paper_2


def long_scenario(folder: Path) -> Path:
    """paper-2 with a 600-tick first step (its map beside it): a run of several seconds."""
    return long_paper_2(folder, 600, "long")


class Run(RunProcess):
    """``toyroom run --out OUT`` as a real process on the test's own world."""

    def __init__(self, tmp_path: Path, world: str, out: Path) -> None:
        self.out = out
        self.world = world
        super().__init__("--scenario", str(long_scenario(tmp_path)), "--out", str(out), "--world", world)

    def wait_until(self, what: str, condition: Callable[[], bool], timeout: float = 120) -> None:
        """Wait (looking every 20 ms) until ``condition()``, failing if the run ends first."""
        deadline = time.monotonic() + timeout
        while not condition():
            assert self.process.poll() is None, f"the run ended before {what}:\n{self.output()}"
            assert time.monotonic() < deadline, f"no {what} within {timeout} s:\n{self.output()}"
            time.sleep(0.02)

    def states(self) -> list[dict]:
        """The states the run has recorded so far (in its folder, wherever it is)."""
        found = []
        for trace in self.out.parent.glob(f"{self.out.name}*/trace.jsonl"):
            for line in trace.read_text().splitlines():
                try:
                    record = json.loads(line)
                except ValueError:
                    continue  # a line being written
                if record["key"].endswith("/state"):
                    found.append(record["payload"])
        return found


def recover(failed: str, out: Path) -> subprocess.CompletedProcess[str]:
    """Run the ``toyroom infer`` command a ``FAILED`` note gives (as ``python -m toyroom``)."""
    lines = [line.strip() for line in failed.splitlines() if line.strip().startswith("toyroom infer ")]
    assert lines, f"FAILED names no toyroom infer command:\n{failed}"
    argv = shlex.split(lines[-1])[1:]
    assert Path(argv[1]) == out / "trace.jsonl", lines[-1]
    return subprocess.run(
        [sys.executable, "-m", "toyroom", *argv], capture_output=True, text=True, timeout=300, check=False
    )


def mind_ticks(path: Path) -> list[int]:
    with path.open(newline="") as handle:
        return sorted({int(row["tick"]) for row in csv.DictReader(handle)})


@pytest.mark.parametrize("sig", [signal.SIGTERM, signal.SIGINT], ids=["SIGTERM", "SIGINT"])
def test_a_signal_stops_every_node_and_leaves_a_marked_recoverable_folder(
    tmp_path: Path, world: str, sig: signal.Signals
) -> None:
    out = tmp_path / "out"
    run = Run(tmp_path, world, out)
    try:
        run.wait_until("a recorded state and a brain", lambda: bool(run.states()) and "brain" in run.nodes())
        nodes = run.nodes()
        os.kill(run.process.pid, sig)
        status = run.finish(timeout=60)
        assert status == 128 + sig, f"exit status {status}, expected {128 + sig}:\n{run.output()}"
        left = [
            f"{name} (pid {p.pid})" for name, p in nodes.items() if p.is_running() and p.status() != "zombie"
        ]
        assert left == [], f"still running after toyroom run exited: {left}"
        failed = (out / "FAILED").read_text()
        assert f"interrupted by {sig.name}" in failed, failed
        assert (out / "trace.jsonl").stat().st_size > 0 and (out / "events.csv").exists()
        assert not (out / "report.md").exists(), "a report of an unfinished run"
        assert [p.name for p in tmp_path.iterdir() if ".running-" in p.name] == []
        if sig == signal.SIGTERM:  # the note's command recovers the minds of the ticks recorded
            result = recover(failed, out)
            assert result.returncode == 0, result.stderr
            assert mind_ticks(out / "mind.csv")[-1] == max(s["tick"] for s in run.states())
            assert (out / "report.md").exists()
    finally:
        run.close()


def test_an_engine_killed_mid_episode_fails_the_run_with_the_minds_inferred(
    tmp_path: Path, world: str
) -> None:
    out = tmp_path / "out"
    run = Run(tmp_path, world, out)
    try:
        run.wait_until(
            "tick 20 and a brain",
            lambda: any(s["tick"] >= 20 for s in run.states()) and "brain" in run.nodes(),
        )
        nodes = run.nodes()
        assert not any(s["done"] for s in run.states()), "the episode ended too soon for this test"
        nodes["engine"].kill()
        status = run.finish()
        assert status == 1, f"exit status {status}:\n{run.output()}"
        assert not nodes["brain"].is_running() or nodes["brain"].status() == "zombie", (
            "the brain outlived the run"
        )
        failed = (out / "FAILED").read_text()
        assert "the engine was killed by SIGKILL before the episode ended" in failed, failed
        assert "were inferred from it with" in failed and "toyroom infer" in failed, failed
        last = max(s["tick"] for s in run.states())
        assert f"-{last};" in failed, f"FAILED should give the ticks recorded (up to {last}):\n{failed}"
        for name in ("mind.csv", "report.md", "beliefs.png", "preferences.png", "events.csv"):
            assert (out / name).stat().st_size > 0, f"{name} missing:\n{failed}"
        assert mind_ticks(out / "mind.csv")[-1] == last, "the minds of every tick recorded"
        assert f"see {out / 'FAILED'}" in run.output(), run.output()
    finally:
        run.close()


def test_an_engine_killed_after_the_last_tick_leaves_whole_results(tmp_path: Path, world: str) -> None:
    """The brain needs the engine no more once the last state is out: it finishes its outputs."""
    out = tmp_path / "out"
    run = Run(tmp_path, world, out)
    try:
        run.wait_until(
            "the last state", lambda: any(s["done"] for s in run.states()) and "engine" in run.nodes()
        )
        try:
            run.nodes()["engine"].kill()
        except (KeyError, psutil.NoSuchProcess):
            pass  # the brain was done first, and the run stopped its engine: the same results
        status = run.finish()
        assert status == 0, f"exit status {status}:\n{run.output()}"
        assert not (out / "FAILED").exists(), (out / "FAILED").read_text()
        for name in ("mind.csv", "report.md", "beliefs.png", "preferences.png", "events.csv"):
            assert (out / name).stat().st_size > 0, f"{name} missing"
    finally:
        run.close()
