"""The protocol version: ``major.minor``.

A peer with another *major* version cannot be understood: its messages are refused with
:class:`~protocol.errors.VersionMismatch`. A peer with another *minor* version can: minor
versions only add optional fields (which older decoders ignore), so they are a warning.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

from .errors import ProtocolError, VersionMismatch

PROTOCOL_VERSION = "1.7"
"""The version this implementation speaks."""

_VERSION_RE = re.compile(r"^(0|[1-9][0-9]{0,5})\.(0|[1-9][0-9]{0,5})$")


@dataclass(frozen=True, order=True)
class Version:
    """A parsed ``major.minor`` protocol version."""

    major: int
    minor: int

    @classmethod
    def parse(cls, text: str, *, message_type: str | None = None) -> Version:
        """Parse ``"1.0"``; raise :class:`ProtocolError` naming the field when malformed."""
        match = _VERSION_RE.match(text) if isinstance(text, str) else None
        if match is None:
            raise ProtocolError(
                f"expected a version 'major.minor' such as '{PROTOCOL_VERSION}', got {text!r}",
                message_type=message_type,
                field="$.protocol",
            )
        return cls(int(match.group(1)), int(match.group(2)))

    def __str__(self) -> str:
        return f"{self.major}.{self.minor}"


CURRENT = Version.parse(PROTOCOL_VERSION)


def check_version(theirs: str, *, message_type: str | None = None) -> bool:
    """Check a peer's version against ours.

    Returns:
        ``True`` when it is exactly ours, ``False`` when only the minor version differs.

    Raises:
        VersionMismatch: the major versions differ.
        ProtocolError: ``theirs`` is not a ``major.minor`` version.
    """
    if theirs == PROTOCOL_VERSION:  # the usual case, without parsing (every message checks)
        return True
    version = Version.parse(theirs, message_type=message_type)
    if version.major != CURRENT.major:
        raise VersionMismatch(PROTOCOL_VERSION, theirs, message_type=message_type)
    return version == CURRENT
