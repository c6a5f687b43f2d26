"""The conditions an evaluation runs under: how the robot perceives, what kind of minds
the simulated people have, and what kind of episodes they live through.

- ``perception``: ``omniscient`` (the paper's setting: the robot sees every item wherever it
  is) or ``embodied`` (it sees the item spots the visibility table lists from its own cell,
  and infers the rest; the brain's ``perception`` setting);
- ``minds``: ``simple`` (people perceive exactly, remember and keep to themselves, which is
  what the brain's percept filter assumes: ``perceptonly`` is then an oracle of their
  beliefs whenever the robot sees everything) or ``rich`` (they forget, overlook, gossip,
  wander: ``python -m sim2d generate --minds``) or ``model`` (they perceive as simple ones do
  and act by the brain's planner under the evaluation's settings, so their parameters are
  known: :mod:`toyroom.evaluation.planned`);
- ``kind``: ``everyday`` (random episodes) or ``tasks`` (built around the robot's jobs: an item
  moved while its owner is away, hidden where they will look last, or wanted by both; a wrong
  place told, overlooked or remembered, which only behaviour shows;
  ``python -m sim2d generate --kind tasks``), drawn in turn from ``tasks`` (default: all of
  :data:`TASK_KINDS`).
"""

from __future__ import annotations

import itertools
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TypeVar

from protocol import MAX_TICKS, Choice, EpisodeKind, EpisodeSpec, Minds, Perception, Policy, TaskKind, task_of

PERCEPTIONS = Perception.names()
MINDS = Minds.names()
KINDS = EpisodeKind.names()
TASK_KINDS = TaskKind.names()
"""The kinds of task episodes, in the generator's order (:func:`protocol.task_of`)."""
POLICIES = Policy.names()
"""The acting robot's policies an evaluation may run (the brain's ``RobotSettings.policy``;
:data:`protocol.OBSERVING`, the robot observing, is always run)."""


@dataclass(frozen=True)
class Condition:
    """One condition of an evaluation."""

    perception: Perception = Perception.OMNISCIENT
    minds: Minds = Minds.SIMPLE
    kind: EpisodeKind = EpisodeKind.EVERYDAY
    tasks: tuple[TaskKind, ...] = ()
    """The task kinds a ``tasks`` condition draws from, in turn by episode seed (empty: all)."""
    autonomy: tuple[str, ...] = ()
    """``NAME=VALUE`` settings of the simulated people's ``[autonomy]`` table, over the ones
    drawn (``python -m sim2d generate --autonomy``, which checks them): the same episodes with
    people who behave otherwise in one respect."""

    def __post_init__(self) -> None:
        malformed = [s for s in self.autonomy if not s.partition("=")[0].strip() or "=" not in s]
        if malformed:
            raise ValueError(f"autonomy settings are NAME=VALUE, not {', '.join(map(repr, malformed))}")
        object.__setattr__(self, "tasks", task_kinds(self.tasks))  # names given as text: their kinds
        for name, value, known in (
            ("perception", self.perception, PERCEPTIONS),
            ("minds", self.minds, MINDS),
            ("kind", self.kind, KINDS),
        ):
            if value not in known:
                raise ValueError(f"{name} must be one of {', '.join(known)}, not {value!r}")

    @property
    def name(self) -> str:
        """``omniscient-simple-everyday``: the condition's folder and key."""
        return f"{self.perception}-{self.minds}-{self.kind}"

    def task_of(self, seed: int) -> str | None:
        """The task kind of the episode of ``seed`` (``None`` unless ``kind`` is ``tasks``), as
        the generator picks it (:func:`protocol.task_of`)."""
        return task_of(seed, self.tasks or TASK_KINDS) if self.kind == EpisodeKind.TASKS else None

    def spec(self, max_ticks: int = MAX_TICKS) -> EpisodeSpec:
        """How this condition's episodes are drawn, ``max_ticks`` long."""
        return EpisodeSpec(self.minds, self.kind, max_ticks, self.tasks, self.autonomy)

    def brain_args(self) -> tuple[str, ...]:
        """What every brain of this condition is told (its perception)."""
        told = self.perception != Perception.OMNISCIENT
        return ("--set", f"perception={self.perception}") if told else ()


def conditions(
    perceptions: Sequence[str],
    minds: Sequence[str],
    kinds: Sequence[str],
    tasks: Sequence[str] = (),
    autonomy: Sequence[str] = (),
) -> list[Condition]:
    """Every combination, in the order given, each ``tasks`` condition drawing from ``tasks``,
    all with the people's ``autonomy`` settings (raises ``ValueError`` naming a bad value)."""
    return [
        Condition(
            chosen(Perception, "perception", p),
            chosen(Minds, "minds", m),
            chosen(EpisodeKind, "kind", k),
            task_kinds(tasks) if k == EpisodeKind.TASKS else (),
            tuple(autonomy),
        )
        for p, m, k in itertools.product(perceptions, minds, kinds)
    ]


def task_kinds(tasks: Sequence[str]) -> tuple[TaskKind, ...]:
    """``tasks`` (names of :class:`protocol.TaskKind`) as their kinds, in order.

    Raises:
        ValueError: ``task kinds are some of moved, ..., not NAME, ...``, naming every bad one.
    """
    bad = [task for task in tasks if task not in TASK_KINDS]
    if bad:
        raise ValueError(f"task kinds are some of {', '.join(TASK_KINDS)}, not {', '.join(bad)}")
    return tuple(TaskKind(task) for task in tasks)


C = TypeVar("C", bound=Choice)


def chosen(choices: type[C], name: str, value: str) -> C:
    """``value`` as one of ``choices``, the value of setting ``name`` (raises ``ValueError``
    naming the setting and its choices)."""
    if value not in choices.names():
        raise ValueError(f"{name} must be one of {', '.join(choices.names())}, not {value!r}")
    return choices(value)
