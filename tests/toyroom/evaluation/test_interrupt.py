"""``toyroom eval`` stopped by a signal: it stops within seconds, keeps every finished
episode and says so, exits 128 + N, and the same command then finishes it with the metrics of
an uninterrupted run; an unfinished evaluation of another command is refused, ``--fresh``
discards it. Real processes: the evaluator, its engines and brains over loopback Zenoh."""

from __future__ import annotations

import json
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

EVAL = ("eval", "--episodes", "3", "--seed", "2", "--workers", "1", "--batch", "1")
SMALL = ("--max-ticks", "150", "--policies", "none", "--out", "e")
"""Three short episodes, one at a time, each a process pair of its own; ``--out e`` relative,
so that every run of it, in a folder of its own, has the same command line in metrics.json."""
STOP_BOUND_S = 20.0
"""The issue asks for a stop within 5 s (typically 0.2 s here); this bound is generous
for a loaded 2-core machine, where stopping the nodes alone may take seconds."""


def _eval(folder: Path, *extra: str, timeout: float = 300) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "toyroom", *EVAL, *SMALL, *extra],
        cwd=folder,
        capture_output=True,
        text=True,
        timeout=timeout,
    )


def _without_timing(path: Path) -> dict:
    """metrics.json without ``timing`` (seconds of this machine, which no two runs share)."""
    metrics = json.loads(path.read_text())
    metrics.pop("timing")
    return metrics


def _descendants_alive(pid: int) -> list[str]:
    """Node processes started by process ``pid`` that are still running (they carry its pid
    in ``TOYROOM_PARENT_PID``)."""
    alive = []
    for proc in Path("/proc").iterdir():
        try:
            environ = (proc / "environ").read_bytes().split(b"\0")
        except OSError:
            continue
        if f"TOYROOM_PARENT_PID={pid}".encode() in environ:
            alive.append((proc / "cmdline").read_bytes().replace(b"\0", b" ").decode()[:200])
    return alive


def _stopped(folder: Path, sig: signal.Signals) -> tuple[subprocess.CompletedProcess[str], float, int]:
    """The evaluation in ``folder`` stopped by ``sig`` once its first episode is kept: its
    result, the seconds from the signal to its exit, and how many episodes it had kept."""
    log = folder / "e" / "episodes.jsonl"
    with (folder / "stdout").open("w") as out, (folder / "stderr").open("w") as err:
        process = subprocess.Popen(
            [sys.executable, "-m", "toyroom", *EVAL, *SMALL], cwd=folder, stdout=out, stderr=err, text=True
        )
        deadline = time.monotonic() + 240
        while not (log.exists() and log.read_text().endswith("\n")):  # a whole line: one episode
            assert process.poll() is None, f"it exited ({process.returncode}) before keeping an episode"
            assert time.monotonic() < deadline, "no episode finished in 240 s"
            time.sleep(0.05)
        process.send_signal(sig)
        sent = time.monotonic()
        try:
            process.wait(timeout=120)
        finally:
            process.kill()
        took = time.monotonic() - sent
    alive = _descendants_alive(process.pid)
    assert alive == [], f"expected every node stopped with the evaluation, still running: {alive}"
    kept = len(log.read_text().splitlines())
    result = subprocess.CompletedProcess(
        process.args, process.returncode, (folder / "stdout").read_text(), (folder / "stderr").read_text()
    )
    return result, took, kept


@pytest.fixture(scope="module")
def uninterrupted(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """The output folder of the same evaluation, never stopped."""
    folder = tmp_path_factory.mktemp("uninterrupted")
    result = _eval(folder)
    assert result.returncode == 0, result.stderr[-2000:]
    return folder / "e"


def test_sigint_keeps_the_finished_episodes_and_the_same_command_finishes(
    uninterrupted: Path, tmp_path: Path
) -> None:
    stopped, took, kept = _stopped(tmp_path, signal.SIGINT)
    assert took < STOP_BOUND_S, f"expected a stop within {STOP_BOUND_S} s of SIGINT, it took {took:.1f} s"
    assert stopped.returncode == 130, f"expected exit 130, got {stopped.returncode}: {stopped.stderr}"
    said = (
        f"toyroom eval: stopped by SIGINT: kept {kept} of 3 episodes in e/episodes.jsonl; "
        "run the same command again to finish"
    )
    assert stopped.stderr.strip().splitlines()[-1:] == [said], f"expected {said!r}, got:\n{stopped.stderr}"
    assert not (tmp_path / "e" / "metrics.json").exists(), "a stopped evaluation passed off as complete"

    resumed = _eval(tmp_path)
    assert resumed.returncode == 0, resumed.stderr[-2000:]
    assert f"toyroom eval: resuming the unfinished evaluation in e: {kept} of 3 episodes kept" in (
        resumed.stdout
    ), resumed.stdout[:2000]
    ran = json.loads((tmp_path / "e" / "metrics.json").read_text())
    assert ran["timing"]["seconds"] > 0
    expected, got = (
        _without_timing(uninterrupted / "metrics.json"),
        _without_timing(tmp_path / "e" / "metrics.json"),
    )
    assert got == expected, "a stopped and resumed evaluation's metrics differ from an uninterrupted one's"
    assert not (tmp_path / "e" / "unfinished-eval.json").exists(), "a finished evaluation left its state"


def test_sigterm_stops_it_and_another_command_is_refused_until_fresh(tmp_path: Path) -> None:
    stopped, took, kept = _stopped(tmp_path, signal.SIGTERM)
    assert took < STOP_BOUND_S, f"expected a stop within {STOP_BOUND_S} s of SIGTERM, it took {took:.1f} s"
    assert stopped.returncode == 143, f"expected exit 143, got {stopped.returncode}: {stopped.stderr}"
    assert f"stopped by SIGTERM: kept {kept} of 3 episodes" in stopped.stderr, stopped.stderr

    other = _eval(tmp_path, "--max-ticks", "100")
    assert other.returncode == 2, f"expected exit 2, got {other.returncode}: {other.stderr}"
    lines = other.stderr.strip().splitlines()
    assert len(lines) == 1 and "e holds an unfinished evaluation of another command" in lines[0], lines
    assert "--max-ticks: 150, now 100" in lines[0] and "--fresh" in lines[0], lines[0]

    fresh = _eval(tmp_path, "--episodes", "1", "--fresh")
    assert fresh.returncode == 0, fresh.stderr[-2000:]
    assert "resuming" not in fresh.stdout, fresh.stdout[:2000]
    entries = (tmp_path / "e" / "episodes.jsonl").read_text().splitlines()
    assert [json.loads(line)["index"] for line in entries] == [0], "--fresh kept the discarded episodes"
    assert len(list((tmp_path / "e").glob("toyroom-eval-*"))) == 1, "--fresh kept the old scratch folder"


def test_the_stop_message_names_what_was_kept() -> None:
    from toyroom.evaluation.interrupt import EvaluationStopped

    cases = {
        EvaluationStopped(signal.SIGINT, 0, 40, Path("e/episodes.jsonl")): (
            "stopped by SIGINT: no episode had finished (40 to run); nothing kept"
        ),
        EvaluationStopped(signal.SIGTERM, 7, 40, Path("e/episodes.jsonl")): (
            "stopped by SIGTERM: kept 7 of 40 episodes in e/episodes.jsonl; "
            "run the same command again to finish"
        ),
    }
    for error, expected in cases.items():
        assert str(error) == expected, f"expected {expected!r}, got {str(error)!r}"
