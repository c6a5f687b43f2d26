"""What the brain remembers of a household: plain, typed data (no I/O).

A :class:`Snapshot` is the brain's own reading of a household at one tick of one day: for each
person, P(each goal is the one they want most) and where they believe each item is (the
brain's estimate, as published in ``brain/mind``), and where the robot itself believes each
item rests. Nothing in it comes from the engine's truth channel.
"""

from __future__ import annotations

import msgspec

from protocol import Mind

Distribution = dict[str, float]
"""Probabilities by id (a goal: an item id or ``out``; or a location id)."""


class PersonMemory(msgspec.Struct, frozen=True):
    """One person as the brain last read them.

    Attributes:
        person: the person's id.
        preference: P(each goal is the most wanted): item ids and ``out``.
        beliefs: item id -> where the person believes it is (location id -> probability).
    """

    person: str
    preference: Distribution
    beliefs: dict[str, Distribution]


class Snapshot(msgspec.Struct, frozen=True):
    """The brain's memory of ``household`` at ``tick`` of day ``day`` (1 = the first day).

    Attributes:
        final: whether this is the end of the day (what the next day starts from), or a
            checkpoint within it (what a brain restarted mid-day resumes from).
        people: one entry per person the brain has read.
        items: item id -> where the robot itself believes it rests (location id -> probability).
    """

    household: str
    day: int
    tick: int
    final: bool
    people: tuple[PersonMemory, ...]
    items: dict[str, Distribution]

    def person(self, person: str) -> PersonMemory | None:
        """The memory of ``person``, if the snapshot has one."""
        return next((p for p in self.people if p.person == person), None)


def snapshot_of(
    household: str, day: int, mind: Mind, items: dict[str, Distribution], *, final: bool
) -> Snapshot:
    """The snapshot of ``household`` on ``day`` read off a ``brain/mind`` message and the
    robot's own item knowledge ``items``."""
    people = tuple(
        PersonMemory(
            person=agent.agent,
            preference={prob.id: prob.p for prob in agent.preference},
            beliefs={b.item: {prob.id: prob.p for prob in b.locations} for b in agent.beliefs},
        )
        for agent in mind.agents
    )
    return Snapshot(household, day, mind.tick, final, people, dict(items))
