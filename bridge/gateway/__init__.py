"""The WebSocket gateway: one world's protocol for clients without Zenoh (Unity, C#).

Frames are :mod:`protocol.frames`; :class:`Gateway` serves them; ``python -m
bridge.gateway`` (``toyroom gateway``) runs one until interrupted.
"""

from .link import ClientLink, LinkSettings
from .server import DEFAULT_PORT, DEFAULT_URL, Gateway, GatewaySettings, parse_listen, read_secret

__all__ = [
    "DEFAULT_PORT",
    "DEFAULT_URL",
    "ClientLink",
    "Gateway",
    "GatewaySettings",
    "LinkSettings",
    "parse_listen",
    "read_secret",
]
