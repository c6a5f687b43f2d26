"""The floors of the command line's time flags, each stated with its reason and refused
before anything starts, in one line naming the flag and the value (exit 2). The settings'
own floors (``decision_seconds``, the robot's timeouts) are the brain's
(:mod:`brain.robotsettings`), a scenario's ``tick_seconds`` is sim2d's loader's, and
``--lease-ms`` is :func:`bridge.session.lease_ms`'s; ``docs/usage.md`` lists them all."""

from __future__ import annotations

import argparse
import math

MIN_SPEED = 1e-3
"""The slowest ``toyroom replay --speed`` other than 0 (a thousand times slower than real time)."""
MIN_REQUEST_TIMEOUT = 1.0
"""The shortest ``--timeout`` of ``toyroom run`` (per lock-step request; 0: none) and
``toyroom conform`` (per request), in seconds: a step is answered in milliseconds, but a loaded
machine or a large house's first step takes up to seconds, and a request that times out ends
the run (or fails the check) for no fault of the engine."""


def _timeout_problem(timeout: float, none: bool) -> str | None:
    """Why ``--timeout`` ``timeout`` is refused (``none``: 0 means no limit), or ``None``."""
    if (none and timeout == 0) or (math.isfinite(timeout) and timeout >= MIN_REQUEST_TIMEOUT):
        return None
    zero = "0 (no limit) or " if none else ""
    return (
        f"--timeout {timeout:g}: expected {zero}at least {MIN_REQUEST_TIMEOUT:g} s (a request that "
        "times out sooner fails for no fault of the engine)"
    )


def time_problem(args: argparse.Namespace) -> str | None:
    """What is wrong with a time flag of ``args`` (below its floor, negative, not finite),
    in one line, or ``None``."""
    if args.command == "run":
        return _timeout_problem(args.timeout, none=True)
    if args.command == "conform":
        return _timeout_problem(args.timeout, none=False)
    if args.command != "replay":
        return None
    if not (args.speed == 0 or MIN_SPEED <= args.speed < math.inf):
        return (
            f"--speed {args.speed}: expected 0 (as fast as possible) or a number of times real time "
            f"from {MIN_SPEED:g}"
        )
    if not (math.isfinite(args.wait_subscribers) and args.wait_subscribers >= 0):
        return f"--wait-subscribers {args.wait_subscribers}: expected a number of seconds >= 0 (0: no wait)"
    return None
