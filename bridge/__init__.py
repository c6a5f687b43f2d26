"""toyroom's bridge: Zenoh sessions, typed messaging, liveliness, lock-step, node processes
(the core, here), and the tools built on it: ``recording``, ``conformance``, ``view``,
``evaluation`` and ``app`` (the ``toyroom`` CLI).

``bridge`` depends on ``protocol`` only; it starts engines and brains as processes and
never imports them.
"""

from .bridge import Bridge
from .errors import BridgeError, ConfigError, NoReply, Refused, RemoteError, StepTimeout
from .handshake import handshake, serve_info
from .lockstep import LockstepClient
from .presence import Peer, PresenceEvent, PresenceWatcher, Token
from .processes import node_command, source_file, start_node, stop_node, stop_on_signals, wait_for_stop
from .pubsub import Congestion, Publisher, Received, Subscriber
from .queries import Queryable, query
from .session import (
    Router,
    SessionSettings,
    build_config,
    is_loopback,
    open_session,
    world_endpoint,
    world_port,
)

__all__ = [
    "node_command",
    "source_file",
    "start_node",
    "stop_node",
    "stop_on_signals",
    "wait_for_stop",
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
    "serve_info",
    "world_endpoint",
    "world_port",
]
