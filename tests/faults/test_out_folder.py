"""``toyroom run``'s results folder under two faults: a second run into the same ``--out``
while the first is on (refused at its start, naming the first: both finishing would lose one's
results), and a full disk (one line naming the file that could not be written, exit 1, not a
traceback per message)."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
from support import long_paper_2

pytestmark = pytest.mark.process

RUN_LIMIT_S = 120.0
"""Most seconds a run may take here: a few unloaded; generous, for a loaded 2-core machine."""


def toyroom_run(*args: str) -> list[str]:
    return [sys.executable, "-m", "toyroom", "run", "--no-live", *args]


def endless_scenario(folder: Path) -> Path:
    """paper-2 whose first step lasts 100,000 ticks: a run that is on until it is stopped."""
    return long_paper_2(folder, 100_000, "endless")


def wait_for_state(trace: Path, process: subprocess.Popen[bytes]) -> None:
    """Wait (looking every 20 ms) until ``trace`` holds an engine state."""
    deadline = time.monotonic() + RUN_LIMIT_S
    while not (trace.is_file() and b'/engine/state"' in trace.read_bytes()):
        assert process.poll() is None, f"the first run ended (exit {process.returncode}) before a state"
        assert time.monotonic() < deadline, f"no state in {trace} within {RUN_LIMIT_S} s"
        time.sleep(0.02)


def test_a_second_run_into_the_same_folder_is_refused_naming_the_first(tmp_path: Path) -> None:
    out = tmp_path / "out"
    log = tempfile.TemporaryFile()
    first = subprocess.Popen(
        toyroom_run("--scenario", str(endless_scenario(tmp_path)), "--out", str(out)),
        stdout=log,
        stderr=subprocess.STDOUT,
    )
    try:
        wait_for_state(tmp_path / f"out.running-{first.pid}" / "trace.jsonl", first)
        second = subprocess.run(
            toyroom_run("--scenario", "paper-robot", "--out", str(out)),
            capture_output=True,
            text=True,
            timeout=RUN_LIMIT_S,
            check=False,
        )
        expected = (
            f"toyroom run: --out {out} is being written by another toyroom run (process {first.pid}); "
            "wait for it to end or name another folder"
        )
        assert (second.returncode, second.stderr.strip()) == (2, expected), (
            f"exit 2 and the line {expected!r} expected; got exit {second.returncode}, "
            f"stderr {second.stderr.strip()!r}, stdout {second.stdout.strip()[-300:]!r}"
        )
        assert first.poll() is None, "the first run must go on"
        os.kill(first.pid, signal.SIGTERM)
        assert first.wait(timeout=RUN_LIMIT_S) == 128 + signal.SIGTERM
    finally:
        if first.poll() is None:
            first.kill()
            first.wait()
        log.close()
    assert (out / "FAILED").read_text().startswith("toyroom run did not finish: interrupted by SIGTERM")
    left = sorted(p.name for p in tmp_path.iterdir() if p.name.startswith("out"))
    assert left == ["out"], f"only the first run's folder expected beside it, no lock left; found {left}"


@pytest.fixture
def full_disk(tmp_path: Path) -> Iterator[Path]:
    """A 1 MiB tmpfs (paper-robot's trace alone is about 3 MB); skipped where it cannot be
    mounted (not root, or no CAP_SYS_ADMIN)."""
    disk = tmp_path / "disk"
    disk.mkdir()
    mounted = subprocess.run(
        ["mount", "-t", "tmpfs", "-o", "size=1m", "tmpfs", str(disk)],
        capture_output=True,
        text=True,
        check=False,
    )
    if mounted.returncode != 0:
        pytest.skip(f"cannot mount a small tmpfs here: {mounted.stderr.strip()}")
    yield disk
    subprocess.run(["umount", "-l", str(disk)], check=False)


def fails_in_one_line(out: Path, written: str, *args: str) -> None:
    """``toyroom run --scenario paper-robot --out OUT ARGS`` fails with exit 1 and the one line
    saying the disk filled while writing ``written`` (no traceback per message)."""
    run = subprocess.run(
        toyroom_run("--scenario", "paper-robot", "--out", str(out), *args),
        capture_output=True,
        text=True,
        timeout=RUN_LIMIT_S,
        check=False,
    )
    lines = [line for line in run.stderr.splitlines() if line.strip()]
    expected = (
        f"toyroom run: no space left on device writing {written}; partial outputs in {out}/, see {out}/FAILED"
    )
    assert (run.returncode, lines) == (1, [expected]), (
        f"exit 1 and the one line {expected!r} expected; got exit {run.returncode} and "
        f"{len(lines)} lines ({run.stderr.count('Traceback')} tracebacks), the last {lines[-3:]}"
    )


def test_a_full_disk_fails_the_run_in_one_line(full_disk: Path) -> None:
    out = full_disk / "out"
    fails_in_one_line(out, "trace.jsonl")
    assert (out / "FAILED").read_text().startswith("toyroom run did not finish: no space left on device")


def test_a_recording_on_a_full_disk_fails_the_run_in_one_line(full_disk: Path, tmp_path: Path) -> None:
    """``--record FILE.mcap`` on a full disk: the recording stops at its first failed write
    (no traceback per message) and the run fails, saying so: what it asked for is lost."""
    fails_in_one_line(tmp_path / "out", "run.mcap", "--record", str(full_disk / "run.mcap"))
