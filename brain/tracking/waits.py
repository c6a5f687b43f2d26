"""Waiting as evidence in proportion to its length (pure): how many of the planner's Stay
decisions a person has made by standing on their cell since their last decision.

A move takes one decision time (``ModelSettings.decision_seconds``, the grid engine's tick);
a continuous engine shows it as a change of cell anywhere from a third of that to a little
more (sim2d: 0.3-0.8 s against 0.7 s). So the first Stay is read once the person has stood
``ModelSettings.wait_decisions`` decision times since their last decision (1.5: the move's
own decision time and half of one more, for that jitter), and one more for each further
decision time: ``floor(t / decision_seconds - (wait_decisions - 1))``. The count is the same
whether it is read while the person stands or when their next decision shows (on the grid
engine, a one-step stop is a move two ticks after the last: one Stay, then the move).
"""

from __future__ import annotations

import math

from ..settings import ModelSettings

TOLERANCE = 1e-6
"""In decision times: a pause that lasts exactly a threshold (up to rounding) reaches it."""


def stays_due(seconds: float, settings: ModelSettings) -> int:
    """How many Stays ``seconds`` of standing since the last decision make (0 when
    ``wait_decisions`` is 0: waits are ignored)."""
    if settings.wait_decisions <= 0:
        return 0
    decisions = seconds / settings.decision_seconds - (settings.wait_decisions - 1.0)
    return max(0, math.floor(decisions + TOLERANCE))
