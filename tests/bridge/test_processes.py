"""Node processes start with single-threaded BLAS unless the user chose otherwise, and stop
when the process that started them is gone."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import time

from bridge.processes import BLAS_THREADS, PARENT_VARIABLE, node_environment, start_node

PRINT_ENV = f"import os; print(' '.join(os.environ.get(n, '-') for n in {BLAS_THREADS!r}))"


def run_and_read(tmp_path, monkeypatch, **env: str) -> str:
    for name in BLAS_THREADS:
        monkeypatch.delenv(name, raising=False)
    for name, value in env.items():
        monkeypatch.setenv(name, value)
    log = tmp_path / "node.log"
    process = start_node([sys.executable, "-c", PRINT_ENV], log)
    assert process.wait(timeout=30) == 0, log.read_text()
    return log.read_text().strip()


def test_a_node_gets_one_blas_thread(tmp_path, monkeypatch):
    got = run_and_read(tmp_path, monkeypatch)
    assert got == "1 1 1", f"expected every BLAS thread count set to 1, got {got!r}"


def test_a_users_blas_threads_are_kept(tmp_path, monkeypatch):
    got = run_and_read(tmp_path, monkeypatch, OPENBLAS_NUM_THREADS="4")
    assert got == "4 1 1", f"expected the user's OPENBLAS_NUM_THREADS=4 kept, got {got!r}"


NODE = (
    "import threading; from bridge.processes import wait_for_stop; "
    "wait_for_stop(threading.Event()); print('stopped', flush=True)"
)
PARENT = f"""
import os, signal, sys
from pathlib import Path
from bridge.processes import start_node
node = start_node([sys.executable, "-c", {NODE!r}], Path(sys.argv[1]))
Path(sys.argv[2]).write_text(str(node.pid))
os.kill(os.getpid(), signal.SIGKILL)  # dies without stopping its node
"""


def test_a_node_whose_starter_was_killed_stops(tmp_path):
    """``toyroom eval`` killed outright used to leave its engines running for good."""
    log, pid = tmp_path / "node.log", tmp_path / "node.pid"
    killed = subprocess.run([sys.executable, "-c", PARENT, str(log), str(pid)], timeout=60, check=False)
    assert killed.returncode == -signal.SIGKILL, f"expected the parent killed, got {killed.returncode}"
    deadline = time.monotonic() + 30
    while "stopped" not in log.read_text() and time.monotonic() < deadline:
        time.sleep(0.1)
    assert "stopped" in log.read_text(), (
        f"expected node {pid.read_text()} to stop once its parent was gone; its log: {log.read_text()!r}"
    )
    assert "is gone: stopping" in log.read_text(), "the node says why it stopped"


def test_a_node_that_replaces_its_starter_keeps_what_it_inherited(monkeypatch):
    monkeypatch.delenv(PARENT_VARIABLE, raising=False)
    assert PARENT_VARIABLE not in node_environment(child=False), "exec'd by hand: no parent to watch"
    monkeypatch.setenv(PARENT_VARIABLE, "12345")
    assert node_environment(child=False)[PARENT_VARIABLE] == "12345"
    assert node_environment()[PARENT_VARIABLE] == str(os.getpid())


def test_a_brain_whose_starter_is_killed_does_not_run_on() -> None:
    """``python -m brain`` waiting for an engine that never comes, started by a process that
    is then killed outright (SIGKILL: no chance to stop its children), stops by itself."""
    import os
    import signal
    import subprocess
    import sys
    import uuid

    import psutil

    world = f"orphan-{uuid.uuid4().hex[:8]}"
    brain_command = f"{sys.executable} -m brain --world {world} --log-level ERROR"
    script = f"export TOYROOM_PARENT_PID=$$; {brain_command} & echo $!; wait"
    starter = subprocess.Popen(["bash", "-c", script], stdout=subprocess.PIPE, text=True)
    assert starter.stdout is not None
    brain = psutil.Process(int(starter.stdout.readline()))
    try:
        os.kill(starter.pid, signal.SIGKILL)
        starter.wait(timeout=10)
        gone, _ = psutil.wait_procs([brain], timeout=20)
        assert gone, "the brain was still running 20 s after the process that started it was killed"
    finally:
        if brain.is_running():
            brain.kill()
