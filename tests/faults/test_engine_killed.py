"""The engine is killed mid-episode: the brain reports it lost within about a second, keeps
its estimates, and carries on when an engine for the same world comes back (with a new
model when the scene changed)."""

from __future__ import annotations

import queue
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest
from support import EngineProcess

from bridge import Bridge, handshake
from protocol import Mind

SCENARIOS = Path(__file__).resolve().parents[2] / "sim2d" / "scenarios"


def start_brain(world: str, *args: str) -> tuple[subprocess.Popen[str], queue.Queue[tuple[float, str]]]:
    """A brain process and its log lines, each stamped with when it was read."""
    brain = subprocess.Popen(
        [sys.executable, "-m", "brain", "--world", world, "--log-level", "WARNING", *args],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        text=True,
    )
    lines: queue.Queue[tuple[float, str]] = queue.Queue()

    def read_log() -> None:
        assert brain.stderr is not None
        for line in brain.stderr:
            lines.put((time.monotonic(), line))

    threading.Thread(target=read_log, daemon=True).start()
    return brain, lines


def test_brain_survives_an_engine_restart(world: str) -> None:
    minds: queue.Queue[Mind] = queue.Queue()
    engine = EngineProcess(world, "--scenario", "paper-robot", "--realtime", "1")
    brain, lines = start_brain(world, "--timeout", "60")
    try:
        with Bridge(world) as watcher:
            handshake(watcher, client="test", timeout=30.0)
            watcher.subscribe(watcher.keys.mind, lambda m, _: minds.put(m), expected=Mind)
            minds.get(timeout=30)  # the brain follows the engine
            killed_at = time.monotonic()
            engine.process.kill()
            engine.process.wait(timeout=30)
            at, line = lines.get(timeout=30)
            assert "lost" in line, line
            assert at - killed_at < 1.5, f"the brain noticed {at - killed_at:.2f} s after the engine died"
            assert brain.poll() is None, "the brain must wait for the engine, not die"
            with EngineProcess(world, "--scenario", "sally-anne", "--realtime", "2"):
                at, line = lines.get(timeout=30)
                assert "back with another scene" in line, line  # a new model for the new scene
                while not minds.empty():
                    minds.get_nowait()
                mind = minds.get(timeout=30)
                assert {a.agent for a in mind.agents} == {"sally", "anne"}, (
                    "estimates of the new scene's people"
                )
                assert brain.poll() is None
    finally:
        brain.kill()
        engine.close()


def test_lockstep_brain_resumes_after_an_engine_restart(world: str) -> None:
    minds: queue.Queue[Mind] = queue.Queue()
    engine = EngineProcess(world, "--scenario", "paper-auto")
    brain, lines = start_brain(world, "--scenario", "paper-auto")
    try:
        with Bridge(world) as watcher:
            watcher.subscribe(watcher.keys.mind, lambda m, _: minds.put(m), expected=Mind)
            minds.get(timeout=30)
            killed_at = time.monotonic()
            engine.process.kill()
            engine.process.wait(timeout=30)
            at, line = lines.get(timeout=30)
            assert "lost" in line and at - killed_at < 2.5, (line, at - killed_at)
            with EngineProcess(world, "--scenario", "paper-auto"):
                at, line = lines.get(timeout=30)
                assert "back" in line, line
                assert brain.wait(timeout=120) == 0, "the brain should finish the episode on the new engine"
    finally:
        if brain.poll() is None:
            brain.kill()
        engine.close()


@pytest.mark.parametrize("engine", ["grid", "csharp", "godot"])
def test_a_gateway_engine_killed_and_restarted_is_handled_as_a_zenoh_one(
    world: str, tmp_path: Path, engine: str
) -> None:
    """The grid engine (Python, C# under Mono, or GDScript under godot3-server) through
    ``toyroom gateway``: killed, the gateway withdraws its token and the brain reports it lost;
    a new engine on the same gateway lets the brain finish."""
    from support import CSharpEngineProcess, GatewayProcess, GodotEngineProcess, GridEngineProcess

    def start(url: str) -> EngineProcess:
        if engine == "csharp":
            return CSharpEngineProcess(url, tmp_path / "exports", str(scenario))
        if engine == "godot":
            return GodotEngineProcess(url, tmp_path / "exports", str(scenario))
        return GridEngineProcess(world, "--scenario", str(scenario), "--gateway", url)

    minds: queue.Queue[Mind] = queue.Queue()
    # paper-2 with a long first step, so that the engine dies mid-episode (the grid engine
    # and the brain run the paper's 60 ticks in a fraction of a second)
    scenario = tmp_path / "long.toml"
    (tmp_path / "paper.map.toml").write_text((SCENARIOS / "paper.map.toml").read_text())
    text = (SCENARIOS / "paper-2.toml").read_text()
    long_play = '{ do = "play", ticks = 600, label = "0" }'
    scenario.write_text(text.replace('{ do = "play", ticks = 20, label = "0" }', long_play))
    assert long_play in scenario.read_text(), "paper-2's first step is no longer what this test lengthens"
    with GatewayProcess(world) as gateway:
        running = start(gateway.url)
        brain, lines = start_brain(world, "--scenario", str(scenario), "--max-ticks", "700")
        try:
            with Bridge(world) as watcher:
                watcher.subscribe(watcher.keys.mind, lambda m, _: minds.put(m), expected=Mind)
                minds.get(timeout=30)
                killed_at = time.monotonic()
                running.process.kill()
                running.process.wait(timeout=30)
                try:
                    at, line = lines.get(timeout=30)
                except queue.Empty:
                    raise AssertionError(
                        f"expected the brain to report the {engine} engine lost, it said nothing in "
                        f"30 s (exit status {brain.poll()}); gateway log:\n{gateway.output()}"
                    ) from None
                assert "lost" in line and at - killed_at < 2.5, (
                    f"expected 'lost' within 2.5 s, got {line!r} after {at - killed_at:.2f} s"
                )
                assert gateway.process.poll() is None, "the gateway must outlive its engine"
                with start(gateway.url) as again:
                    at, line = lines.get(timeout=30)
                    assert "back" in line, f"expected the brain to see the engine back, got {line!r}"
                    finished = brain.wait(timeout=120)
                    assert finished == 0, (
                        f"expected the brain to finish the episode on the new engine, it exited "
                        f"{finished}; engine log:\n{again.output()}"
                    )
        finally:
            if brain.poll() is None:
                brain.kill()
            running.close()


def test_an_engine_lost_and_back_in_the_same_episode_gets_new_command_ids(world: str) -> None:
    """An engine frozen past its link's lease (as under heavy load) is lost to the brain, then
    comes back with the same episode and remembers every command id it was sent: the brain's
    commands after the link comes back must not reuse one (the engine refuses a duplicate)."""
    import signal

    from protocol import CommandStatus

    statuses: queue.Queue[CommandStatus] = queue.Queue()
    engine = EngineProcess(world, "--scenario", "paper-robot", "--realtime", "1")
    brain, lines = start_brain(world, "--timeout", "60")
    try:
        with Bridge(world) as watcher:
            handshake(watcher, client="test", timeout=30.0)
            watcher.subscribe(watcher.keys.status(), lambda s, _: statuses.put(s), expected=CommandStatus)
            before = statuses.get(timeout=60)  # the robot has sent a command
            engine.process.send_signal(signal.SIGSTOP)
            try:
                at, line = lines.get(timeout=30)
                assert "lost" in line, line
            finally:
                engine.process.send_signal(signal.SIGCONT)
            at, line = lines.get(timeout=30)
            assert "is back: carrying on" in line, line
            while not statuses.empty():
                statuses.get_nowait()
            after = statuses.get(timeout=60)  # a command sent over the link that came back
            seen = [after]
            deadline = time.monotonic() + 2
            while time.monotonic() < deadline:
                try:
                    seen.append(statuses.get(timeout=0.5))
                except queue.Empty:
                    pass
            duplicates = [s for s in seen if "duplicate" in (s.reason or "")]
            assert not duplicates, f"first command {before.command}; after the link came back: {duplicates}"
            assert brain.poll() is None
    finally:
        brain.kill()
        engine.close()
