"""toyroom's bridge: Zenoh sessions, typed messaging, liveliness, lock-step and the CLI.

``bridge`` depends on ``protocol`` only; it starts engines and brains as processes and
never imports them.
"""

from .bridge import Bridge
from .errors import BridgeError, ConfigError, NoReply, Refused, RemoteError, StepTimeout
from .handshake import handshake, serve_info
from .lockstep import LockstepClient
from .presence import Peer, PresenceEvent, PresenceWatcher, Token
from .pubsub import Congestion, Publisher, Queryable, Received, Subscriber, query
from .router import Router, run_router
from .session import SessionSettings, build_config, is_loopback, open_session, world_endpoint, world_port

__all__ = [
    "Bridge",
    "BridgeError",
    "ConfigError",
    "Congestion",
    "LockstepClient",
    "NoReply",
    "Peer",
    "PresenceEvent",
    "PresenceWatcher",
    "Publisher",
    "Queryable",
    "Received",
    "Refused",
    "RemoteError",
    "Router",
    "SessionSettings",
    "StepTimeout",
    "Subscriber",
    "Token",
    "build_config",
    "handshake",
    "is_loopback",
    "open_session",
    "query",
    "run_router",
    "serve_info",
    "world_endpoint",
    "world_port",
]
