"""The brain node with a memory file (``python -m brain --memory FILE``) against a real sim2d
engine: a day's end is saved, the next day starts from it, a brain that joins a day late
starts from its checkpoint, and a file it cannot use stops it at once with its name."""

from __future__ import annotations

import subprocess
import sys
import threading
import time
from collections.abc import Callable
from pathlib import Path

from support import EngineProcess, run_brain

from brain.memory import open_memory
from bridge import Bridge, Received
from protocol import Mind
from sim2d.scenario.maps import SCENARIO_DIR

TICKS = 120


def household_day(folder: Path, day: int) -> Path:
    """``paper-auto`` as day ``day`` of household ``h1``."""
    text = (SCENARIO_DIR / "paper-auto.toml").read_text()
    path = folder / f"h1-day{day}.toml"
    path.write_text(
        text.replace('name = "paper-auto"', f'name = "h1-day{day}"')
        + f'\n[household]\nid = "h1"\nday = {day}\n'
    )
    return path


def first_mind(world: str, *args: str) -> tuple[Mind, str]:
    """Run a lock-step brain to ``TICKS``; its tick-0 mind (from the wire) and its log."""
    minds: dict[int, Mind] = {}
    lock = threading.Lock()

    def keep(mind: Mind, _: Received) -> None:
        with lock:
            minds.setdefault(mind.tick, mind)

    with Bridge(world) as watcher:
        watcher.subscribe(watcher.keys.mind, keep, expected=Mind)
        brain = run_brain(world, "--max-ticks", str(TICKS), *args, "--log-level", "INFO")
        assert brain.returncode == 0, brain.stderr[-3000:]
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline and max(minds, default=-1) < TICKS:
            time.sleep(0.05)
    with lock:
        assert 0 in minds, f"expected the brain's tick-0 mind on the wire, got ticks {sorted(minds)[:5]}"
        return minds[0], brain.stderr


def preference(mind: Mind, person: str) -> dict[str, float]:
    agent = next(a for a in mind.agents if a.agent == person)
    return {p.id: p.p for p in agent.preference}


def test_a_day_saved_is_the_next_days_start(world: str, tmp_path: Path) -> None:
    memory = tmp_path / "memory.sqlite"
    day1, day2 = household_day(tmp_path, 1), household_day(tmp_path, 2)
    with EngineProcess(world, "--scenario", str(day1), "--lockstep"):
        _, log1 = first_mind(
            world, "--scenario", str(day1), "--memory", str(memory), "--checkpoint-ticks", "50"
        )
        assert "household 'h1' day 1: nothing remembered before it" in log1, log1[-2000:]
        with open_memory(memory) as store:
            end = store.morning("h1", 2)
        assert end is not None and end.final and end.tick == TICKS, (
            f"expected day 1's end at tick {TICKS}: {end}"
        )
        assert {p.person for p in end.people} == {"A1", "A2"}, end
        mind, log2 = first_mind(world, "--scenario", str(day2), "--memory", str(memory))
        assert "household 'h1' day 2: starting from day 1's end" in log2, log2[-2000:]
        fresh, _ = first_mind(world, "--scenario", str(day2))
    for person in ("A1", "A2"):
        remembered = end.person(person)
        assert remembered is not None
        learned, got = remembered.preference, preference(mind, person)
        expected = {g: 0.9 * p + 0.1 / 3 for g, p in learned.items()}  # memory_drift = 0.1, 3 goals
        assert all(abs(got[g] - expected[g]) < 0.03 for g in expected), (
            f"{person}: expected day 2 to start from day 1's {learned} with drift 0.1, got {got}"
        )
        even = preference(fresh, person)
        assert all(abs(p - 1 / 3) < 0.03 for p in even.values()), f"without memory the prior is even: {even}"


def test_a_memory_file_the_brain_cannot_use_stops_it_at_start(world: str, tmp_path: Path) -> None:
    bad = tmp_path / "memory.sqlite"
    bad.write_bytes(b"\x00garbage" * 100)
    started = time.monotonic()
    brain = run_brain(world, "--memory", str(bad), "--handshake-timeout", "30", timeout=60)
    assert brain.returncode == 2, f"expected exit 2, got {brain.returncode}: {brain.stderr[-2000:]}"
    lines = brain.stderr.strip().splitlines()
    assert lines and lines[-1].startswith(f"brain: memory file {bad} is not a toyroom memory"), lines[-3:]
    assert time.monotonic() - started < 30, "refused before waiting for any engine"


def test_a_read_only_memory_file_stops_the_brain_at_start(
    world: str, tmp_path: Path, read_only: Callable[[Path], None]
) -> None:
    """Not at its first save, mid-run, with a traceback."""
    path = tmp_path / "memory.sqlite"
    open_memory(path).close()
    read_only(path)
    brain = run_brain(world, "--memory", str(path), "--handshake-timeout", "30", timeout=60)
    assert brain.returncode == 2, f"expected exit 2, got {brain.returncode}: {brain.stderr[-2000:]}"
    lines = brain.stderr.strip().splitlines()
    assert lines and lines[-1].startswith(f"brain: memory file {path} cannot be written"), lines[-3:]
    assert "Traceback" not in brain.stderr, brain.stderr[-2000:]


def test_a_brain_that_joins_a_day_late_starts_from_its_checkpoint(world: str, tmp_path: Path) -> None:
    """A real-time engine plays day 2 of a household; a brain that saves a checkpoint every 20
    ticks follows it and is killed (SIGKILL: no day's end is saved); a brain started again
    joins the day where the engine is, and starts from that checkpoint, not from the morning."""
    memory = tmp_path / "memory.sqlite"
    day2 = household_day(tmp_path, 2)
    brain = [sys.executable, "-m", "brain", "--world", world, "--memory", str(memory), "--log-level", "INFO"]
    ticks: list[int] = []
    with EngineProcess(world, "--scenario", str(day2), "--realtime", "4"), Bridge(world) as watcher:
        watcher.subscribe(watcher.keys.mind, lambda m, _: ticks.append(m.tick), expected=Mind)
        first = subprocess.Popen([*brain, "--checkpoint-ticks", "20"], stderr=subprocess.PIPE, text=True)
        try:
            deadline = time.monotonic() + 60
            followed = lambda: max(ticks, default=0) - min(ticks, default=0)  # noqa: E731
            while time.monotonic() < deadline and followed() < 80:  # it may join late, under load
                time.sleep(0.05)
            assert followed() >= 80, f"the brain never followed the engine 80 ticks: {first.poll()}"
        finally:
            first.kill()
            first.communicate(timeout=10)
        with open_memory(memory) as store:
            kept = store.resume("h1", 2)
        assert kept is not None and not kept.final and kept.tick >= 20, f"expected a checkpoint: {kept}"
        again = subprocess.Popen(brain, stderr=subprocess.PIPE, text=True)
        try:
            assert again.stderr is not None
            wanted = f"household 'h1' day 2: starting from day 2's checkpoint at tick {kept.tick}"
            seen = []
            for line in again.stderr:
                seen.append(line)
                if wanted in line or "starting from" in line or len(seen) > 200:
                    break
        finally:
            again.kill()
            again.communicate(timeout=10)
    assert any(wanted in line for line in seen), f"expected {wanted!r}, got:\n{''.join(seen[-20:])}"
