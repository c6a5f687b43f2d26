"""The WebSocket gateway: one world's protocol for clients without Zenoh (Unity, C#).

Frames are :mod:`protocol.frames`; :class:`Gateway` serves them; ``python -m
toyroom.gateway`` (``toyroom gateway``) runs one until interrupted, and :func:`start_gateway`
starts that process. Part of the application, not of the wire: it is a node built on
:mod:`bridge`, as the engine and the brain are (it moved from ``bridge.gateway``, issue 68).
"""

from .link import ClientLink, LinkSettings
from .process import GATEWAY_READY, gateway_command, start_gateway
from .server import DEFAULT_PORT, DEFAULT_URL, Gateway, GatewaySettings, parse_listen, read_secret

__all__ = [
    "DEFAULT_PORT",
    "DEFAULT_URL",
    "GATEWAY_READY",
    "ClientLink",
    "Gateway",
    "GatewaySettings",
    "LinkSettings",
    "gateway_command",
    "parse_listen",
    "read_secret",
    "start_gateway",
]
