"""No child process (the meshcat server, Chromium and its helpers) outlives ``toyroom view``,
whether it ends on SIGINT, on SIGTERM, by ``timeout``, or is stopped mid-screenshot."""

from __future__ import annotations

import signal
import subprocess
import sys
import time
from collections.abc import Callable
from pathlib import Path

import pytest

from toyroom.view.server import SERVER_MODULE

VIEW = [sys.executable, "-m", "toyroom", "view"]


def _stat(pid: int) -> tuple[str, int] | None:
    """(state, parent pid) of a process, or None when it is gone."""
    try:
        text = Path(f"/proc/{pid}/stat").read_text()
    except (FileNotFoundError, ProcessLookupError):
        return None
    fields = text[text.rindex(")") + 2 :].split()
    return fields[0], int(fields[1])


def descendants(pid: int) -> set[int]:
    """Every living descendant of ``pid``."""
    parents = {}
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit() and (stat := _stat(int(entry.name))) is not None:
            parents[int(entry.name)] = stat[1]
    found, frontier = set(), {pid}
    while frontier:
        frontier = {child for child, parent in parents.items() if parent in frontier} - found
        found |= frontier
    return found


def groups() -> dict[int, set[int]]:
    """Process group id -> its running (not zombie) members."""
    found: dict[int, set[int]] = {}
    for entry in Path("/proc").iterdir():
        try:
            text = (entry / "stat").read_text() if entry.name.isdigit() else ""
        except (FileNotFoundError, ProcessLookupError):
            continue
        if text:
            fields = text[text.rindex(")") + 2 :].split()
            if fields[0] != "Z":
                found.setdefault(int(fields[2]), set()).add(int(entry.name))
    return found


def alive(pid: int) -> bool:
    stat = _stat(pid)
    return stat is not None and stat[0] != "Z"


def cmdline(pid: int) -> str:
    try:
        return Path(f"/proc/{pid}/cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace")
    except (FileNotFoundError, ProcessLookupError):
        return ""


def wait_for(what: str, found: Callable[[], set[int]], limit: float = 60.0) -> set[int]:
    """Poll ``found`` (every 20 ms) until it returns something; fail naming ``what``."""
    deadline = time.monotonic() + limit
    while time.monotonic() < deadline:
        if result := found():
            return result
        time.sleep(0.02)
    pytest.fail(f"no {what} appeared within {limit:g} s")


def meshcat_server(root: int) -> set[int]:
    return {p for p in descendants(root) if SERVER_MODULE in cmdline(p)}


def assert_all_gone(pids: set[int], how: str) -> None:
    left = {p: cmdline(p) for p in pids if alive(p)}
    assert not left, f"after {how}, expected no child left; still running: {left}"


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM], ids=["SIGINT", "SIGTERM"])
def test_signals_stop_the_meshcat_server_too(world: str, sig: signal.Signals) -> None:
    viewer = subprocess.Popen([*VIEW, "--world", world], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
    try:
        wait_for("meshcat server", lambda: meshcat_server(viewer.pid))
        children = descendants(viewer.pid)
        viewer.send_signal(sig)
        _, err = viewer.communicate(timeout=30)
    finally:
        viewer.kill()
    assert viewer.returncode == 0, f"the viewer exited {viewer.returncode} on {sig.name}: {err.decode()}"
    assert_all_gone(children, sig.name)


def test_timeout_stops_the_meshcat_server_too(world: str) -> None:
    timed = subprocess.Popen(["timeout", "6", *VIEW, "--world", world], stdout=subprocess.DEVNULL)
    try:
        wait_for("meshcat server", lambda: meshcat_server(timed.pid))
        children = descendants(timed.pid)
        timed.wait(timeout=60)
    finally:
        timed.kill()
    assert timed.returncode == 124, (
        f"expected timeout's 124 (the viewer ran until stopped), got {timed.returncode}"
    )
    assert_all_gone(children, "`timeout 6 toyroom view`")


def test_sigterm_mid_screenshot_stops_chromium(living_world: str, tmp_path: Path) -> None:
    shot = tmp_path / "view.png"
    viewer = subprocess.Popen(  # a world with an engine and a brain: the viewer starts Chromium
        [*VIEW, "--world", living_world, "--screenshot", str(shot), "--after", "1"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
    )
    try:
        chromium = wait_for(
            "chromium", lambda: {p for p in descendants(viewer.pid) if "chromium" in cmdline(p)}
        )
        children = descendants(viewer.pid)
        viewer.send_signal(signal.SIGTERM)
        _, err = viewer.communicate(timeout=30)
    finally:
        viewer.kill()
    assert viewer.returncode == 1 and b"stopped before the screenshot" in err, (
        f"expected exit 1 and 'stopped before the screenshot', got {viewer.returncode}: {err.decode()}"
    )
    assert_all_gone(children, "SIGTERM mid-screenshot")
    for leader in chromium & set(groups()):  # helpers Chromium started after the snapshot too
        deadline = time.monotonic() + 10
        while groups().get(leader) and time.monotonic() < deadline:
            time.sleep(0.05)
        left = {pid: cmdline(pid) for pid in groups().get(leader, ())}
        assert not left, f"Chromium's process group {leader} still has running members: {left}"
