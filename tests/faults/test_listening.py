"""Every server the project starts listens on loopback only: ``toyroom view`` (its Zenoh
session and its meshcat server's web and ZMQ ports), ``toyroom play`` (with a participant's
world running: its engine and brain), ``toyroom rate``, ``toyroom gateway``, ``toyroom sim``
and ``toyroom router``. Each runs as a real process with its loopback defaults (a port of
0 where the default port is a fixed one, so that tests do not collide); every TCP socket
listening and every UDP socket bound in its process tree (read with psutil) must be on
127.0.0.0/8 or ::1, none on 0.0.0.0 or [::]: Zenoh's own listeners and scouting included."""

from __future__ import annotations

import ipaddress
import re
import socket
import subprocess
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path

import psutil
import pytest
from support import free_port, toyroom_run
from websockets.sync.client import connect

from tests.toyroom.devtools import wait_until
from tests.toyroom.output import OutputLines

pytestmark = pytest.mark.process

TOYROOM = [sys.executable, "-m", "toyroom"]
STARTUP_S = 120.0
"""The most to wait for a server's sockets (a loaded machine starts a brain slowly)."""


def is_loopback(ip: str) -> bool:
    """Whether a socket's local address is a loopback one (an IPv4-mapped one included)."""
    address = ipaddress.ip_address(ip.split("%")[0])
    if isinstance(address, ipaddress.IPv6Address) and address.ipv4_mapped is not None:
        address = address.ipv4_mapped
    return address.is_loopback


@dataclass(frozen=True)
class Listener:
    """A socket that listens: TCP listening, or UDP bound and unconnected."""

    process: str
    """Its process: the command line and the pid."""
    kind: str
    """``tcp`` or ``udp``."""
    ip: str
    port: int

    def __str__(self) -> str:
        return f"{self.kind} {self.ip}:{self.port} of {self.process}"


def listening(root: int) -> list[Listener]:
    """Every TCP socket listening and every unconnected UDP socket of ``root`` and its
    descendants."""
    found = []
    try:
        parent = psutil.Process(root)
        processes = [parent, *parent.children(recursive=True)]
    except psutil.NoSuchProcess:
        return []
    for process in processes:
        try:
            sockets = process.net_connections(kind="inet")
            name = f"`{' '.join(process.cmdline())}` (pid {process.pid})"
        except (psutil.NoSuchProcess, psutil.ZombieProcess):
            continue
        for s in sockets:
            if s.type == socket.SOCK_STREAM and s.status == psutil.CONN_LISTEN:
                found.append(Listener(name, "tcp", s.laddr.ip, s.laddr.port))
            elif s.type == socket.SOCK_DGRAM and not s.raddr:
                found.append(Listener(name, "udp", s.laddr.ip, s.laddr.port))
    return found


@contextmanager
def server(command: list[str], name: str) -> Iterator[OutputLines]:
    """``command`` as a process (its output collected); stopped with SIGTERM at the end."""
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    try:
        yield OutputLines(process, name)
    finally:
        process.terminate()
        try:
            process.wait(timeout=30)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait(timeout=10)


def assert_loopback_only(output: OutputLines, at_least: int) -> None:
    """Wait until the process tree of ``output``'s process has ``at_least`` sockets
    listening, then check that every one (by then) is on loopback."""
    process = output.process

    def enough() -> list[Listener] | None:
        assert process.poll() is None, (
            f"`{output.name}` exited {process.returncode}:\n" + "\n".join(output.lines)
        )
        found = listening(process.pid)
        return found if len(found) >= at_least else None

    wait_until(enough, STARTUP_S, f"{at_least} listening sockets of `{output.name}`")
    found = listening(process.pid)
    wide = [str(listener) for listener in found if not is_loopback(listener.ip)]
    assert wide == [], (
        f"expected `{output.name}` to listen on loopback only; it listens beyond it on: {wide} "
        f"(all its listening sockets: {[str(listener) for listener in found]})"
    )


def test_view_listens_on_loopback_only(world: str) -> None:
    """The viewer's Zenoh session, and its meshcat server's ZMQ and web ports."""
    with server([*TOYROOM, "view", "--world", world], "toyroom view") as output:
        output.wait(r"toyroom view: world .* at http://127\.0\.0\.1:\d+/", STARTUP_S)
        assert_loopback_only(output, 3)


def test_sim_listens_on_loopback_only(world: str) -> None:
    with server([*TOYROOM, "sim", "--world", world, "--realtime", "1"], "toyroom sim") as output:
        output.wait(r"sim2d: scenario", STARTUP_S)
        assert_loopback_only(output, 1)


def test_gateway_listens_on_loopback_only(world: str) -> None:
    """Its WebSocket server and its Zenoh session."""
    command = [*TOYROOM, "gateway", "--world", world, "--listen", "ws://127.0.0.1:0"]
    with server(command, "toyroom gateway") as output:
        output.wait(r"\(ready\)", STARTUP_S)
        assert_loopback_only(output, 2)


def test_router_listens_on_loopback_only() -> None:
    endpoint = f"tcp/127.0.0.1:{free_port()}"
    with server([*TOYROOM, "router", "--listen", endpoint], "toyroom router") as output:
        output.wait(r"toyroom router listening on", STARTUP_S)
        assert_loopback_only(output, 1)


def test_play_and_a_participants_world_listen_on_loopback_only(tmp_path: Path) -> None:
    """The page's server, and once a participant's page connects, the Zenoh sessions of
    their world: the server's own, the engine's and the brain's."""
    command = [*TOYROOM, "play", "--scenario", "paper-robot", "--as", "A1", "--participants", "1",
               "--listen", "127.0.0.1:0", "--out", str(tmp_path), "--log-level", "WARNING"]  # fmt: skip
    with server(command, "toyroom play") as output:
        link = output.wait(r"participant p1: http://", STARTUP_S).split(": ", 2)[-1]
        page = re.sub(r"^http://([^/]+)/play/", r"ws://\1/ws/", link)
        with connect(page, open_timeout=30):  # starts the participant's world
            assert_loopback_only(output, 4)


QUESTIONS = """
[[questions]]
recording = "short"
tick = 20
person = "A1"
ask = "desire"
"""


def test_rate_listens_on_loopback_only(tmp_path: Path) -> None:
    scenario = Path(__file__).parents[2] / "sim2d" / "scenarios" / "paper-1.toml"
    short = tmp_path / "short.toml"  # paper-1 for 40 ticks: a recording in seconds
    short.write_text(re.sub(r"(?m)^max_ticks = \d+", "max_ticks = 40", scenario.read_text()))
    toyroom_run(tmp_path / "run", str(short), "--no-live", "--record", str(tmp_path / "short.mcap"))
    (tmp_path / "q.toml").write_text(QUESTIONS)
    command = [*TOYROOM, "rate", str(tmp_path / "short.mcap"), "--questions", str(tmp_path / "q.toml"),
               "--out", str(tmp_path / "a.csv"), "--listen", "http://127.0.0.1:0"]  # fmt: skip
    with server(command, "toyroom rate") as output:
        output.wait(r"toyroom rate: ready", STARTUP_S)
        assert_loopback_only(output, 1)
