"""Errors raised by the protocol package.

One root (:class:`Error`) and specific subclasses. Every failure to turn bytes into a
message is a :class:`ProtocolError` that names the message type (when it could be read)
and the offending field (as a JSON path such as ``$.agents[0].cell.col``).
"""

from __future__ import annotations


class Error(Exception):
    """Root of every error raised by ``protocol``."""


class ProtocolError(Error):
    """A payload is not a valid message of this protocol.

    Attributes:
        message_type: the ``type`` tag of the message, or ``None`` when it could not be read.
        field: JSON path of the offending field (``$.tick``), or ``None`` for the whole payload.
        reason: what was expected and what came instead.
        key: the Zenoh key the payload arrived on, when known.
    """

    def __init__(
        self,
        reason: str,
        *,
        message_type: str | None = None,
        field: str | None = None,
        key: str | None = None,
    ) -> None:
        self.reason = reason
        self.message_type = message_type
        self.field = field
        self.key = key
        super().__init__(self._render())

    def _render(self) -> str:
        what = f"'{self.message_type}' message" if self.message_type else "message"
        where = f" at field {self.field}" if self.field else ""
        on = f" on key '{self.key}'" if self.key else ""
        return f"invalid {what}{on}{where}: {self.reason}"

    def on_key(self, key: str) -> ProtocolError:
        """Return the same error with the Zenoh key it arrived on filled in."""
        self.key = key
        self.args = (self._render(),)
        return self


class VersionMismatch(ProtocolError):
    """The peer speaks another major version of the protocol.

    Attributes:
        ours: the protocol version this side speaks (``"1.1"``).
        theirs: the version the peer declared.
    """

    def __init__(
        self, ours: str, theirs: str, *, message_type: str | None = None, key: str | None = None
    ) -> None:
        self.ours = ours
        self.theirs = theirs
        super().__init__(
            f"protocol version mismatch: this side speaks {ours}, the peer speaks {theirs}"
            " (major versions differ, so the messages cannot be read)",
            message_type=message_type,
            field="$.protocol",
            key=key,
        )
