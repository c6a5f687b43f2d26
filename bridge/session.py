"""Zenoh sessions with a safe default and explicit overrides.

The default is a *peer* that never leaves the machine: multicast scouting off, listening
on ``127.0.0.1`` only, on a port derived from the world name (so two worlds on one machine
do not meet). The first session of a world listens on that port; later ones find it taken,
listen on an ephemeral loopback port instead and connect to the world port, and gossip
joins them all into a mesh. When the listener goes away, the next session to open takes
the port over and the others reconnect to it.

Overrides: a Zenoh JSON5 config file, or flags for the mode (``peer``, ``client``,
``router``) and the listen / connect endpoints (e.g. a router on another machine).
"""

from __future__ import annotations

import argparse
import json
import logging
import re
import zlib
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Literal

import zenoh

from protocol import ProtocolError, check_name

from .errors import ConfigError

log = logging.getLogger("toyroom.bridge")

Mode = Literal["peer", "client", "router"]

PORT_BASE = 17000
PORT_SPAN = 10000
LOOPBACK = "127.0.0.1"
_ENDPOINT_RE = re.compile(r"^(?P<proto>[a-z0-9]+)/(?P<host>\[[^\]]+\]|[^:/?#]+)(:(?P<port>\d+))?")


def world_port(world: str) -> int:
    """The default TCP port of a world: ``17000 + crc32(world) % 10000`` (stable, below
    Linux's ephemeral range)."""
    return PORT_BASE + zlib.crc32(check_name(world).encode()) % PORT_SPAN


def world_problem(world: str) -> str | None:
    """What is wrong with ``--world`` ``world`` (a name that cannot be a key chunk:
    :func:`protocol.check_name`), in one line, or ``None``: a command checks it before it
    starts anything."""
    try:
        check_name(world)
    except ProtocolError as err:
        return f"--world: {err.reason}"
    return None


def world_endpoint(world: str) -> str:
    """The default loopback endpoint of a world, e.g. ``tcp/127.0.0.1:23511``."""
    return f"tcp/{LOOPBACK}:{world_port(world)}"


def is_loopback(endpoint: str) -> bool:
    """Whether a Zenoh endpoint (``tcp/127.0.0.1:7447``) stays on this machine."""
    match = _ENDPOINT_RE.match(endpoint)
    if match is None:
        return False
    host = match.group("host").strip("[]").lower()
    return host == "localhost" or host == "::1" or host.startswith("127.")


DEFAULT_LEASE_MS = 800
"""How long a silent link is kept (ms): a node stalled for longer is taken for gone."""
MIN_LEASE_MS, MAX_LEASE_MS = 100, 60_000


@dataclass(frozen=True)
class SessionSettings:
    """How to open a session. Fields left ``None`` take the safe default.

    Attributes:
        mode: ``peer`` (default), ``client`` (through a router) or ``router``;
            ``None`` keeps the config file's mode, or ``peer`` without a file.
        listen: endpoints to listen on; default: the world port on loopback (peer, router).
        connect: endpoints to connect to; default: the world port on loopback.
        config_file: a Zenoh JSON5 config to start from (flags still override it).
        lease_ms: how long this session's peers keep its link while it is silent (a stall:
            SIGSTOP, a loaded machine), in milliseconds; past it they take it for gone. A
            killed process closes its links, so it is noticed at once whatever the lease.
        scout_delay_ms: how long, in milliseconds, opening a peer session may wait for the
            peers it learns of to connect (Zenoh's ``scouting/delay``). Zenoh's default, 500,
            is paid in full by the first session of a world, which has nobody to wait for,
            so every run of an engine and a brain started half a second late per session; a
            session joining a world returns as soon as its peers are connected, well within
            this.
    """

    mode: Mode | None = None
    listen: tuple[str, ...] | None = None
    connect: tuple[str, ...] | None = None
    config_file: Path | None = None
    lease_ms: int = DEFAULT_LEASE_MS
    scout_delay_ms: int = 100
    extra: tuple[tuple[str, str], ...] = field(default=())
    """Further ``(path, json5 value)`` config insertions, applied last."""


def _insert(config: zenoh.Config, path: str, value: object) -> None:
    try:
        config.insert_json5(path, json.dumps(value))
    except Exception as err:  # zenoh.ZError
        raise ConfigError(f"cannot set Zenoh config '{path}' to {value!r}: {err}") from None


def build_config(
    world: str, settings: SessionSettings, *, listen: tuple[str, ...] | None = None
) -> zenoh.Config:
    """The Zenoh config for ``world`` under ``settings`` (``listen`` overrides both)."""
    if settings.config_file is not None:
        try:
            config = zenoh.Config.from_file(str(settings.config_file))
        except Exception as err:
            raise ConfigError(f"cannot read Zenoh config file {settings.config_file}: {err}") from None
    else:
        config = zenoh.Config()
        _insert(config, "scouting/multicast/enabled", False)
        _insert(config, "transport/link/tx/lease", settings.lease_ms)
        _insert(config, "scouting/delay", settings.scout_delay_ms)
        _insert(config, "transport/link/tx/keep_alive", 4)
        _insert(
            config,
            "connect/retry",
            {"period_init_ms": 100, "period_max_ms": 1000, "period_increase_factor": 2},
        )
    defaults = settings.config_file is None  # fill in the safe defaults only without a file
    mode = settings.mode or ("peer" if defaults else None)
    if mode is not None:
        _insert(config, "mode", mode)
    endpoints_listen = listen if listen is not None else settings.listen
    if endpoints_listen is None and defaults and mode != "client":
        endpoints_listen = (world_endpoint(world),)
    if endpoints_listen is not None:
        _insert(config, "listen/endpoints", list(endpoints_listen))
        for endpoint in endpoints_listen:
            if not is_loopback(endpoint):
                log.warning(
                    "listening on non-loopback endpoint %s: other machines can reach this "
                    "session; use TLS and access control (docs/deployment.md)",
                    endpoint,
                )
    connect = settings.connect
    if connect is None and defaults and mode != "router":
        connect = (world_endpoint(world),)
    if connect is not None:
        _insert(config, "connect/endpoints", list(connect))
    for path, value in settings.extra:
        try:
            config.insert_json5(path, value)
        except Exception as err:
            raise ConfigError(f"cannot set Zenoh config '{path}' to {value}: {err}") from None
    return config


def open_session(world: str, settings: SessionSettings | None = None) -> zenoh.Session:
    """Open a Zenoh session on ``world``'s network.

    With the default settings the session listens on the world port when it is free and
    on an ephemeral loopback port otherwise (see the module docstring).

    Raises:
        ConfigError: the config is invalid or the session cannot be opened; the message
            says which endpoint or setting is at fault.
    """
    settings = settings or SessionSettings()
    default_listen = (
        settings.listen is None and settings.config_file is None and settings.mode in (None, "peer")
    )
    try:
        return zenoh.open(build_config(world, settings))
    except ConfigError:
        raise
    except Exception as err:
        if default_listen and "in use" in str(err):
            fallback = (f"tcp/{LOOPBACK}:0",)
            try:
                return zenoh.open(build_config(world, settings, listen=fallback))
            except Exception as again:
                err = again
        raise ConfigError(f"cannot open a Zenoh session for world '{world}': {err}") from None


def add_network_args(parser: argparse.ArgumentParser, *, world: bool = True) -> None:
    """Add the flags that choose the world and override the Zenoh session."""
    group = parser.add_argument_group("network (default: loopback only, no multicast)")
    if world:
        group.add_argument("--world", default="default", help="world name: the key prefix toyroom/WORLD/")
    group.add_argument("--zenoh-config", type=Path, help="a Zenoh JSON5 config file to start from")
    group.add_argument(
        "--mode", choices=("peer", "client", "router"), help="Zenoh mode (default: peer, or the config's)"
    )
    group.add_argument(
        "--listen", action="append", metavar="ENDPOINT", help="listen endpoint, e.g. tcp/127.0.0.1:7447"
    )
    group.add_argument(
        "--connect", action="append", metavar="ENDPOINT", help="connect endpoint (a router or peer)"
    )
    group.add_argument(
        "--lease-ms",
        type=lease_ms,
        metavar="MS",
        help=f"how long this session's peers keep its link while it is silent (a stall), in ms "
        f"(default {DEFAULT_LEASE_MS}, toyroom run's nodes 8000; {MIN_LEASE_MS}-{MAX_LEASE_MS}); "
        "a killed process is noticed at once",
    )


def settings_from_args(args: argparse.Namespace) -> SessionSettings:
    """The session settings the network flags ask for."""
    return SessionSettings(
        mode=args.mode,
        listen=tuple(args.listen) if args.listen else None,
        connect=tuple(args.connect) if args.connect else None,
        config_file=args.zenoh_config,
        lease_ms=getattr(args, "lease_ms", None) or DEFAULT_LEASE_MS,
    )


def lease_ms(text: str) -> int:
    """``--lease-ms``: a whole number of milliseconds within the allowed range.

    Raises:
        argparse.ArgumentTypeError: naming the value and the range."""
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a whole number of milliseconds, got {text!r}") from None
    if not MIN_LEASE_MS <= value <= MAX_LEASE_MS:
        raise argparse.ArgumentTypeError(f"{value} is outside {MIN_LEASE_MS}-{MAX_LEASE_MS} ms")
    return value


DEFAULT_ROUTER_ENDPOINT = "tcp/127.0.0.1:7447"


class Router:
    """A Zenoh router (the meeting point for nodes on several machines: they connect to its
    endpoint in ``client`` mode or as peers) session listening on ``listen``; a context manager."""

    def __init__(self, listen: Sequence[str], *, config_file: Path | None = None) -> None:
        settings = SessionSettings(
            mode="router",
            listen=tuple(listen) if listen else None,
            connect=() if config_file is None else None,
            config_file=config_file,
        )
        config = build_config("router", settings)
        try:
            self.session = zenoh.open(config)
        except Exception as err:
            raise ConfigError(f"cannot start a Zenoh router on {', '.join(listen)}: {err}") from None
        configured = json.loads(config.get_json("listen/endpoints"))
        if isinstance(configured, dict):  # per-mode defaults
            configured = configured.get("router", [])
        self.listen = tuple(listen) or tuple(configured or ())
        self._closed = False

    def close(self) -> None:
        """Stop the router; safe to call twice."""
        if not self._closed:
            self._closed = True
            self.session.close()

    def __enter__(self) -> Router:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()
