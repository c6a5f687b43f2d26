"""The envelope every message shares.

Every message is a flat JSON object whose first two fields are the envelope::

    {"type": "state", "protocol": "1.1", ...the message's own fields...}

``type`` names the message (its tag) and ``protocol`` the ``major.minor`` version of the
sender. Unknown fields are ignored on decode, which is what lets a minor version add
optional fields without breaking older peers.
"""

from __future__ import annotations

import re
from typing import Annotated

import msgspec

from .version import PROTOCOL_VERSION

ID_PATTERN = r"^[A-Za-z][A-Za-z0-9_-]{0,63}$"
"""What an :data:`Id` matches."""
ID_TEXT = "a letter, then up to 63 letters, digits, '_' or '-'"
"""What an :data:`Id` is, in words."""

Id = Annotated[str, msgspec.Meta(pattern=ID_PATTERN, description=f"An identifier: {ID_TEXT}.")]
"""Identifiers of agents, items, regions, doors, locations and commands (safe in Zenoh keys)."""


def id_problem(value: object) -> str | None:
    """Why ``value`` is no :data:`Id` (one line, naming it), or ``None``: for a reader of ids
    (a scenario loader) to refuse one before any message would carry it."""
    if isinstance(value, str) and re.fullmatch(ID_PATTERN, value):
        return None
    return f"{value!r} is not an id: expected {ID_TEXT} (no spaces or other signs)"


Probability = Annotated[float, msgspec.Meta(ge=0.0, le=1.0)]
"""A probability in [0, 1]."""

Tick = Annotated[int, msgspec.Meta(ge=0, description="Engine tick count since the last reset.")]

Seconds = Annotated[float, msgspec.Meta(ge=0.0, description="Simulated seconds since reset.")]


class Message(msgspec.Struct, frozen=True, kw_only=True, tag_field="type"):
    """Base of every top-level message: the ``type`` tag and the ``protocol`` version."""

    protocol: str = PROTOCOL_VERSION
    """Protocol version of the sender, ``major.minor``."""


class Header(msgspec.Struct, frozen=True):
    """The envelope alone, read first to route and version-check a payload."""

    type: str
    protocol: str
