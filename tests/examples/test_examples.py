"""The examples of ``examples/`` run as real processes, on loopback Zenoh, in seconds: the
tiny engine serves the real brain (``python -m brain``) and passes ``toyroom conform
--strict``; ``watch_minds.py`` prints the brain's minds of it, a false belief included.
They run in the fast tier (``make check``), as zenoh-python's CI runs its examples."""

from __future__ import annotations

import re
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import pytest

pytestmark = [pytest.mark.example, pytest.mark.process]

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"


class Example:
    """``python examples/<script> ARGS`` as a process, its output in a temporary file; a
    context manager that stops it (SIGTERM, then SIGKILL)."""

    def __init__(self, script: str, *args: str) -> None:
        self.log = tempfile.TemporaryFile()
        command = [sys.executable, str(EXAMPLES / script), *args]
        self.process = subprocess.Popen(command, stdout=self.log, stderr=subprocess.STDOUT)

    def output(self) -> str:
        """Everything the example has printed so far."""
        self.log.seek(0)
        return self.log.read().decode(errors="replace")

    def wait_for(self, text: str, timeout: float = 15.0) -> None:
        """Wait until the example has printed ``text``, failing the test after ``timeout`` s."""
        deadline = time.monotonic() + timeout
        while text not in self.output():
            if self.process.poll() is not None or time.monotonic() > deadline:
                pytest.fail(f"{self.process.args[1]} never printed {text!r}:\n{self.output()}")
            time.sleep(0.02)

    def __enter__(self) -> Example:
        return self

    def __exit__(self, *exc: object) -> None:
        if self.process.poll() is None:
            self.process.terminate()
            try:
                self.process.wait(timeout=10)
            except subprocess.TimeoutExpired:
                self.process.kill()
                self.process.wait(timeout=10)
        self.log.close()


def _run(*command: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, *command], capture_output=True, text=True, timeout=60)


def test_the_tiny_engine_serves_the_brain_and_watch_minds_prints_sallys_false_belief(
    world: str, tmp_path: Path
) -> None:
    with (
        Example("tiny_engine.py", "--world", world) as engine,
        Example("watch_minds.py", "--world", world) as watcher,
    ):
        engine.wait_for("(ready)")
        watcher.wait_for("(ready)")
        brain = _run("-m", "brain", "--world", world, "--out", str(tmp_path), "--log-level", "WARNING")
        assert brain.returncode == 0, brain.stdout + brain.stderr
        watcher.wait_for("brain toyroom-brain left")  # the watcher stops on its own
        assert watcher.process.wait(timeout=10) == 0
        printed, watched = engine.output(), watcher.output()
    assert "tick 4: sally in hall, ball in box" in printed  # moved while she was out
    assert "tick 8: sally in room, ball in box" in printed  # the episode's last tick
    minds = {int(m[1]): m[2] for m in re.finditer(r"^tick (\d+) sally: (.*)$", watched, re.M)}
    assert sorted(minds) == list(range(9)), watched  # one mind a tick, ticks 0 to 8
    assert re.fullmatch(r"ball@basket [\d.]+; wants \w+ [\d.]+; false belief: ball", minds[4]), minds[4]
    assert minds[7].startswith("ball@box") and "false belief" not in minds[7], minds[7]  # she saw it
    assert (tmp_path / "mind.csv").is_file()


def test_the_tiny_engine_passes_the_conformance_kit_strict(world: str) -> None:
    with Example("tiny_engine.py", "--world", world) as engine:
        engine.wait_for("(ready)")
        conform = _run("-m", "toyroom", "conform", "--world", world, "--strict")
    assert conform.returncode == 0, conform.stdout + conform.stderr
    assert re.search(r"\d+ passed, 0 skipped, 0 failed", conform.stdout), conform.stdout


def test_drive_engine_resets_and_steps_the_tiny_engine(world: str) -> None:
    with Example("tiny_engine.py", "--world", world) as engine:
        engine.wait_for("(ready)")
        drive = _run(str(EXAMPLES / "drive_engine.py"), "--world", world, "--steps", "3", "--ticks", "2")
    assert drive.returncode == 0, drive.stdout + drive.stderr
    assert drive.stdout.splitlines() == [
        "engine 'tiny 1.0', scenario 'tiny': tick 0: sally in room",
        "tick 2: sally in hall",
        "tick 4: sally in hall",
        "tick 6: sally in room",
    ]
