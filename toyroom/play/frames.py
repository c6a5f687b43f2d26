"""What the participant's page sends, read (pure): one frame, a key press, the start or a
refusal.

The page sends text frames of JSON: ``{"type": "key", "key": K, "pressed": S}``, ``K`` the
browser's ``KeyboardEvent.key`` and ``S`` when it was pressed, in seconds since the page
opened; or ``{"type": "start", "consented": true}`` when the participant presses Start
(``consented``: they ticked the study's consent, when it asks for one). Anything else (not
JSON, JSON nested too deeply to decode, another ``type``, a field of the wrong kind) is a
:class:`FrameRefused`, which the server answers with an ``error`` frame, ``{"type": "error",
"message": ...}``; the world runs on.
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass

from bridge.errors import BridgeError

MAX_KEY = 32
"""Longest key name kept, in characters (the browser's longest, ``AudioVolumeMute``, fits)."""


class FrameRefused(BridgeError):
    """A frame from the page that is not a key press; the message says what was wrong."""


@dataclass(frozen=True)
class KeyPress:
    """One key press on the page."""

    key: str
    """The browser's ``KeyboardEvent.key`` (at most :data:`MAX_KEY` characters)."""
    pressed: float
    """When, in seconds since the page opened (>= 0)."""


@dataclass(frozen=True)
class StartPressed:
    """The participant pressed Start."""

    consented: bool
    """They ticked the study's consent box (``False`` when none was shown)."""


def read_frame(frame: str | bytes) -> KeyPress | StartPressed:
    """The key press or the start in one frame from the page.

    Raises:
        FrameRefused: naming what is wrong with the frame (and how it starts).
    """
    start = frame[:40] if isinstance(frame, str) else frame[:40].decode("utf-8", "replace")
    try:
        message = json.loads(frame)
    except RecursionError:  # the decoder's depth limit: no key press is nested so deeply
        raise FrameRefused(f"not a key press: JSON nested too deeply to decode ({start!r}...)") from None
    except ValueError as err:  # UnicodeDecodeError included
        raise FrameRefused(f"not a key press: not JSON ({err}; {start!r})") from None
    if isinstance(message, dict) and message.get("type") == "start":
        consented = message.get("consented", False)
        if not isinstance(consented, bool):
            raise FrameRefused(f"a start whose 'consented' is not true or false: {consented!r}")
        return StartPressed(consented)
    if not isinstance(message, dict) or message.get("type") != "key":
        expected = 'expected an object with "type": "key" or "start"'
        raise FrameRefused(f"not a key press: {expected}, got {start!r}")
    key, pressed = message.get("key"), message.get("pressed", 0.0)
    if not isinstance(key, str) or not key:
        raise FrameRefused(f"a key press without a key name: 'key' is {key!r}")
    number = isinstance(pressed, int | float) and not isinstance(pressed, bool)
    if not number or not math.isfinite(pressed) or pressed < 0:
        raise FrameRefused(f"a key press whose 'pressed' is not a finite number of seconds >= 0: {pressed!r}")
    return KeyPress(key[:MAX_KEY], float(pressed))
