"""What a participant of a study is told and asked to do: a scenario's optional ``[study]``
section, as ``python -m sim2d study --scenario NAME`` prints it (JSON) and ``toyroom play``
shows it before the clock starts.

Not a wire message: engines never send it. It lives in the protocol so that the scenario's
reader (sim2d) and the study's host (``toyroom play``) agree on one typed form.
"""

from __future__ import annotations

import enum
from typing import Annotated

import msgspec

from .message import Id


class StudyOutcome(enum.Enum):
    """How a participant's episode ended, as its recording says (``toyroom.play`` metadata
    ``outcome``)."""

    GOAL_REACHED = "goal_reached"
    """The study's goal (:class:`Goal`) was met."""
    TIMED_OUT = "timed_out"
    """The time limit (``Study.time_limit`` or the scenario's ``max_ticks``) passed first."""
    ENDED = "ended"
    """The episode ran to its end and the study states no goal to reach."""
    INCOMPLETE = "incomplete"
    """Cut short: the page stayed away past its grace period, a node failed or the server
    stopped (the recording's ``reason`` says which)."""


class Goal(msgspec.Struct, frozen=True, forbid_unknown_fields=True):
    """What the participant's person must do for the goal to count as reached: exactly one of
    ``holds`` (an item id: they hold it), ``plays`` (an item id: they play with it) or
    ``enters`` (a region id: they are in it); with ``after``, only once the person has
    completed the step of their script with that ``label`` (the engine's event of it), so
    that a goal met at the start (holding the toy they begin with) does not count."""

    holds: Id | None = None
    plays: Id | None = None
    enters: Id | None = None
    after: str | None = None

    def problem(self) -> str | None:
        """Why this goal is not one condition (``None``: it is)."""
        given = [name for name in ("holds", "plays", "enters") if getattr(self, name) is not None]
        if len(given) != 1:
            return f"give exactly one of holds, plays or enters (got {', '.join(given) or 'none'})"
        return None


class Study(msgspec.Struct, frozen=True, forbid_unknown_fields=True):
    """A scenario's ``[study]`` section.

    Attributes:
        instructions: who the participant is and what the world is, shown before the start
            (plain text; blank lines separate paragraphs).
        goal: what they are asked to do, in words (shown before the start and beside the map).
        reached: the goal as a condition the host checks each tick (``None``: the episode runs
            until the time limit or its own end).
        time_limit: seconds of world time after which the episode ends, ``timed_out``
            (``None``: the scenario's ``max_ticks``).
        consent: a consent text the participant must agree to before the start (empty: none
            is asked).
    """

    instructions: str = ""
    goal: str = ""
    reached: Goal | None = None
    time_limit: Annotated[float, msgspec.Meta(gt=0.0)] | None = None
    consent: str = ""


__all__ = ["Goal", "StudyOutcome", "Study"]
