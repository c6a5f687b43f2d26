"""SIGTERM reaches a node even when the kernel delivers it to one of Zenoh's native threads
rather than the main thread (a main thread blocked in a bare ``Event.wait()`` would never
run the Python handler: found as engines that ignored SIGTERM in ``toyroom eval``)."""

from __future__ import annotations

import ctypes
import os
import signal
import subprocess
import sys
import time

import pytest

SYS_TGKILL = 234  # x86-64


def other_threads(pid: int) -> list[int]:
    return [int(t) for t in os.listdir(f"/proc/{pid}/task") if int(t) != pid]


def tgkill(pid: int, tid: int, sig: int) -> None:
    libc = ctypes.CDLL(None, use_errno=True)
    if libc.syscall(SYS_TGKILL, pid, tid, sig) != 0:
        raise OSError(ctypes.get_errno(), f"tgkill({pid}, {tid}, {sig}) failed")


@pytest.mark.skipif(not sys.platform.startswith("linux") or os.uname().machine != "x86_64", reason="tgkill")
@pytest.mark.parametrize(
    "command",
    [["-m", "sim2d", "--scenario", "paper-1", "--lockstep"], ["-m", "toyroom", "router"]],
    ids=["sim2d", "router"],
)
def test_sigterm_to_a_native_thread_stops_the_node(world: str, command: list[str]) -> None:
    extra = ["--world", world] if "sim2d" in command else ["--listen", "tcp/127.0.0.1:0"]
    process = subprocess.Popen(
        [sys.executable, *command, *extra], stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True
    )
    try:
        assert process.stdout is not None
        first = process.stdout.readline()
        assert first, "the node printed nothing before exiting"
        time.sleep(0.5)
        threads = other_threads(process.pid)
        assert threads, "expected Zenoh's threads besides the main one"
        tgkill(process.pid, threads[-1], signal.SIGTERM)
        try:
            code = process.wait(timeout=5)
        except subprocess.TimeoutExpired:
            pytest.fail(f"'{' '.join(command)}' ignored a SIGTERM delivered to thread {threads[-1]}")
        assert code == 0, f"exit status {code}"
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
