"""Open vocabularies: named values a newer minor version may extend.

Capabilities, item shapes, region kinds and event kinds are strings on the wire with a
documented *known* set (an :class:`enum.StrEnum` each). A known value decodes to its enum
member, so ``region.kind is RegionKind.OUTSIDE`` works; a value this side does not know is
kept as the plain string it came as (and re-encoded unchanged), and logged once per
vocabulary and value for the life of the process (however many handshakes bring it again),
never a failed decode. An engine of protocol 1.1 or later may use values of its own (a
``corridor`` region, a ``backpack`` shape): that is what the vocabularies are open for.
Code that meets an unknown value treats it as the vocabulary's neutral case (a viewer draws
an unknown shape as a block; the brain reads an unknown region kind as a room and ignores
an unknown event).

Command kinds are open too: :func:`protocol.robot.unknown_action` keeps a command of a kind
this side does not know, so an engine can fail it with a reason instead of dropping it.
"""

from __future__ import annotations

import enum
import logging
import threading
from typing import TypeVar

import msgspec

log = logging.getLogger("protocol.vocabulary")

E = TypeVar("E", bound=enum.StrEnum)

_seen: set[tuple[str, str]] = set()
_lock = threading.Lock()


def described(vocabulary: type[enum.StrEnum], what: str) -> msgspec.Meta:
    """The schema metadata of one value of an open vocabulary: a string, with its known set
    (use as ``Annotated[str, described(RegionKind, "region kind")]``)."""
    values = ", ".join(repr(m.value) for m in vocabulary)
    return msgspec.Meta(
        description=f"A {what}: one of {values}, or another value from a peer of a newer minor "
        "version (kept, and warned about once).",
        examples=[next(iter(vocabulary)).value],
    )


def known(vocabulary: type[E], value: str) -> E | str:
    """``value`` as a member of ``vocabulary`` when it is one, else ``value`` itself (logged
    once per vocabulary and value)."""
    if isinstance(value, vocabulary):
        return value
    try:
        return vocabulary(value)
    except ValueError:
        note_unknown(vocabulary.__name__, value)
        return value


def note_unknown(vocabulary: str, value: str) -> None:
    """Log, once per vocabulary and value, that a peer sent a value this side does not know."""
    key = (vocabulary, value)
    with _lock:
        if key in _seen:
            return
        _seen.add(key)
    log.warning(
        "a peer sent %s %r, which this side (protocol %s) does not list: fine (an open vocabulary), "
        "kept and treated as unknown; said once per value",
        vocabulary,
        value,
        _version(),
    )


def unknown_values() -> set[tuple[str, str]]:
    """Every ``(vocabulary, value)`` met so far that this side does not know."""
    with _lock:
        return set(_seen)


def _version() -> str:
    from .version import PROTOCOL_VERSION

    return PROTOCOL_VERSION
