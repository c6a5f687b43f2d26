"""The floors of the command line's time flags, each stated with its reason and refused
before anything starts, in one line naming the flag and the value (exit 2). The settings'
own floors (``decision_seconds``, the robot's timeouts) are the brain's
(:mod:`brain.robotsettings`), a scenario's ``tick_seconds`` is sim2d's loader's, and
``--lease-ms`` is :func:`bridge.session.lease_ms`'s; ``docs/usage.md`` lists them all. Each
command's module (:mod:`toyroom.cli.commands`) checks its own flags with these."""

from __future__ import annotations

import math

MIN_SPEED = 1e-3
"""The slowest ``toyroom replay --speed`` other than 0 (a thousand times slower than real time)."""
MIN_REQUEST_TIMEOUT = 1.0
"""The shortest ``--timeout`` of ``toyroom run`` (per lock-step request; 0: none) and
``toyroom conform`` (per request), in seconds: a step is answered in milliseconds, but a loaded
machine or a large house's first step takes up to seconds, and a request that times out ends
the run (or fails the check) for no fault of the engine."""


def timeout_problem(timeout: float, none: bool) -> str | None:
    """Why ``--timeout`` ``timeout`` is refused (``none``: 0 means no limit), or ``None``."""
    if (none and timeout == 0) or (math.isfinite(timeout) and timeout >= MIN_REQUEST_TIMEOUT):
        return None
    zero = "0 (no limit) or " if none else ""
    return (
        f"--timeout {timeout:g}: expected {zero}at least {MIN_REQUEST_TIMEOUT:g} s (a request that "
        "times out sooner fails for no fault of the engine)"
    )


def replay_problem(speed: float, wait_subscribers: float) -> str | None:
    """Why ``toyroom replay --speed`` or ``--wait-subscribers`` is refused (below its floor,
    negative, not finite), in one line, or ``None``."""
    if not (speed == 0 or MIN_SPEED <= speed < math.inf):
        return (
            f"--speed {speed}: expected 0 (as fast as possible) or a number of times real time "
            f"from {MIN_SPEED:g}"
        )
    if not (math.isfinite(wait_subscribers) and wait_subscribers >= 0):
        return f"--wait-subscribers {wait_subscribers}: expected a number of seconds >= 0 (0: no wait)"
    return None
