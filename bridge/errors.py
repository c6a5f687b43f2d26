"""Errors raised by the bridge: one root, specific subclasses, each saying what was
expected and what came instead."""

from __future__ import annotations

from protocol import ErrorCode


class BridgeError(Exception):
    """Root of every error raised by ``bridge``."""


class ConfigError(BridgeError):
    """A Zenoh session could not be configured or opened (bad endpoint, config file...)."""


class NoReply(BridgeError):
    """A query got no answer: nobody serves the key, or the answer did not come in time."""


class RemoteError(BridgeError):
    """The peer refused a query with an ``error`` reply.

    Attributes:
        code: the peer's machine-readable reason.
        message: the peer's sentence saying what was wrong.
    """

    def __init__(self, key: str, code: ErrorCode, message: str) -> None:
        self.key = key
        self.code = code
        self.message = message
        super().__init__(f"query on '{key}' refused ({code.value}): {message}")


class StepTimeout(BridgeError):
    """A lock-step request got no answer (or no resulting state) within its timeout."""


class Refused(BridgeError):
    """Raised by a queryable's handler to refuse a request with an ``error`` reply."""

    def __init__(self, code: ErrorCode, message: str) -> None:
        self.code = code
        self.message = message
        super().__init__(f"{code.value}: {message}")
