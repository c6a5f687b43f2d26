"""toyroom's bridge, the wire: Zenoh sessions, typed messaging, liveliness, lock-step, node
processes (the core, here), and the tools of the wire built on it: ``recording`` (trace.jsonl,
MCAP, replay) and ``conformance`` (the engine checks). The application (the ``toyroom``
command line, evaluation, fitting, the study pages, the live view, the WebSocket gateway for
engines without Zenoh: ``toyroom.gateway``) is the ``toyroom`` package, which bridge never
imports. ``tests/test_architecture.py`` holds bridge to its budget of lines.

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
