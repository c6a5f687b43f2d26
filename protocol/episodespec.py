"""What a generated episode is drawn as, beside its map and seed: one value, passed whole.

The episode generator (``sim2d.generation``, ``python -m sim2d generate``) writes episodes to
an :class:`EpisodeSpec`, and the evaluation (``toyroom.evaluation.generation``) asks for them
with one; both take its one default length, :data:`MAX_TICKS`.
"""

from __future__ import annotations

from dataclasses import dataclass

from .choices import EpisodeKind, Minds, TaskKind

MAX_TICKS = 1000
"""A generated episode's length in ticks unless told otherwise (``toyroom eval --max-ticks``'s
documented default, and ``python -m sim2d generate``'s)."""


@dataclass(frozen=True)
class EpisodeSpec:
    """How a generated episode is drawn, whatever its map and seed.

    Attributes:
        minds: what kind of minds its simulated people have.
        kind: what it is about (``tasks``: built around one of the robot's jobs).
        max_ticks: its length: it ends after this many ticks.
        tasks: the task kinds a ``tasks`` episode is drawn from, in turn by seed (names of
            :class:`~protocol.choices.TaskKind`; empty: all of them).
        autonomy: ``NAME=VALUE`` settings of the people's ``[autonomy]`` table, over the drawn
            ones (a TOML value: ``replan_lag=[100000,100000]``; the generator checks them).
    """

    minds: Minds = Minds.SIMPLE
    kind: EpisodeKind = EpisodeKind.EVERYDAY
    max_ticks: int = MAX_TICKS
    tasks: tuple[TaskKind, ...] = ()
    autonomy: tuple[str, ...] = ()


DEFAULT_EPISODE = EpisodeSpec()
"""The episode of a generator told nothing: simple minds, everyday, :data:`MAX_TICKS` long
(the default of every function that takes an :class:`EpisodeSpec`)."""
