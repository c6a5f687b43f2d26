"""The handshake, both sides: a client asks ``engine/info`` with a ``Hello``; the engine
answers with its ``EngineInfo`` or refuses a client of another major version.

A major-version mismatch is an error naming both versions; a minor mismatch is a warning,
said once per peer and version for the life of the process (a brain handshakes again at
every reset, a run's recorder and viewer each once), as values of the open vocabularies
are (:mod:`protocol.vocabulary`).
"""

from __future__ import annotations

import logging
import threading
import time
from collections.abc import Callable

from protocol import PROTOCOL_VERSION, EngineInfo, Hello, Message, check_version, validate_scene

from .bridge import Bridge
from .errors import NoReply
from .queries import Queryable

log = logging.getLogger("toyroom.bridge")

_warned: set[tuple[str, str, str]] = set()
_warned_lock = threading.Lock()


def _first_time(side: str, peer: str, version: str) -> bool:
    """Whether this process meets ``peer`` (an engine or a client) speaking ``version`` for
    the first time; noted, so that its minor-version warning is said once."""
    with _warned_lock:
        if (side, peer, version) in _warned:
            return False
        _warned.add((side, peer, version))
        return True


def handshake(
    bridge: Bridge,
    *,
    client: str,
    role: str = "client",
    timeout: float | None = 5.0,
    hello: Hello | None = None,
) -> EngineInfo:
    """Ask the world's engine who it is.

    Returns:
        the engine's :class:`~protocol.EngineInfo`, its scene checked for consistency.

    Raises:
        VersionMismatch: the engine speaks another major version (both versions named).
        InvalidScene: the engine's scene is inconsistent (every problem listed).
        NoReply: no engine answered within ``timeout`` seconds.
    """
    request = hello if hello is not None else Hello(client=client, role=role)
    info = ask_engine(bridge, request, timeout)
    if not check_version(info.protocol, message_type="engine_info") and _first_time(
        "engine", info.engine, info.protocol
    ):
        log.warning(
            "engine '%s' speaks protocol %s and this side %s: minor versions differ, continuing",
            info.engine,
            info.protocol,
            PROTOCOL_VERSION,
        )
    validate_scene(info.scene)
    return info


def ask_engine(bridge: Bridge, hello: Hello, timeout: float | None) -> EngineInfo:
    """The engine's answer to ``hello``, waiting for an engine that is still starting until
    ``timeout`` seconds pass (``None``: forever); no checks on the answer.

    Raises:
        NoReply: no engine answered in time.
    """
    started = time.monotonic()
    deadline = None if timeout is None else started + timeout
    while True:
        # never a negative timeout (Zenoh refuses one): a late wake-up still asks once more
        remaining = None if deadline is None else max(deadline - time.monotonic(), 0.01)
        try:
            return bridge.query(bridge.keys.info, hello, EngineInfo, timeout=remaining)
        except NoReply:
            if deadline is not None and time.monotonic() + 0.05 >= deadline:
                waited = time.monotonic() - started
                raise NoReply(
                    f"no engine answered the handshake on '{bridge.keys.info}': waited {waited:.1f} s "
                    f"(the limit, {timeout:g} s); is an engine of this world running, or still starting?"
                ) from None
            time.sleep(0.05)


def serve_info(bridge: Bridge, current: Callable[[], EngineInfo]) -> Queryable[Message]:
    """Engine side: answer ``engine/info`` with ``current()``.

    Clients of another major version get a ``version_mismatch`` error reply (the queryable
    does that while decoding their ``Hello``); a minor mismatch is logged as a warning, once
    per client and version.
    """

    def answer(hello: Hello | None, key: str) -> EngineInfo:
        if (
            hello is not None
            and not check_version(hello.protocol, message_type="hello")
            and _first_time("client", hello.client, hello.protocol)
        ):
            log.warning(
                "client '%s' (%s) speaks protocol %s and this engine %s: minor versions differ",
                hello.client,
                hello.role,
                hello.protocol,
                PROTOCOL_VERSION,
            )
        return current()

    return bridge.queryable(bridge.keys.info, answer, expected=(Hello,))
