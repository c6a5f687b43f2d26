"""Households over days (``python -m sim2d generate --days N``, ``toyroom eval --days N``): the
same map, people and items lived day after day.

Day 1 of a household is the single episode of its seed (:func:`~.episodes.episode`), with a
``[household]`` table. Each later day starts from the end of the day before (a
:class:`protocol.Morning`, read off the engine's last truth of that day): items where they were
left, each person sure of what they were sure of at night and wanting what they wanted most.
Then, drawn from the household's seed and the day alone (so every run of a household has the
same nights, whatever its robot did):

- **drift**: each person's favourite is redrawn, with chance :data:`DRIFT` per day, uniformly
  among the other goals (items; and ``out`` in everyday episodes);
- **the night** (:func:`night`): with chance :data:`TIDY` someone tidies (one item not where it
  rested on the household's first morning goes back there; the tidier sees it, nobody else
  does), with chance :data:`VISITOR` a visitor moves an item to another spot (nobody sees), and
  with chance :data:`OUT_AND_BACK` someone takes an item out of the house and, back, leaves it
  at another spot (they know where; nobody else does). So stale beliefs arise by themselves,
  overnight; the robot learns of a change when it sees the place.

The day's episode is then drawn from ``day_seed(seed, day)`` on that morning: homes, habits and
(``--kind tasks``) the day's task, built around the first person's favourite item.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from protocol import MAX_DAYS, Morning

DRIFT = 0.1
"""The chance per day that a person's favourite is redrawn."""
TIDY = 0.3
"""The chance per night that someone puts an item back where it rested on the first morning."""
VISITOR = 0.3
"""The chance per night that a visitor moves an item to another spot, unseen."""
OUT_AND_BACK = 0.1
"""The chance per night that someone takes an item out and leaves it at another spot when back."""


def day_seed(seed: int, day: int) -> int:
    """The seed day ``day`` of the household of ``seed`` is drawn from: ``seed`` on day 1, then
    ``100 seed + day`` (apart from every other household's and day's while days <= 99)."""
    if not 1 <= day <= MAX_DAYS:
        raise ValueError(f"a household's day is from 1 to {MAX_DAYS}, not {day}")
    return seed if day == 1 else 100 * seed + day


@dataclass(frozen=True)
class Change:
    """One thing that happened overnight: ``rule`` moved ``item`` from ``origin`` to
    ``target``; ``seen_by``: the people who know (none but the mover, if any)."""

    rule: str
    item: str
    origin: str
    target: str
    seen_by: tuple[str, ...] = ()

    def comment(self) -> str:
        who = ", ".join(self.seen_by) or "nobody"
        return f"# overnight ({self.rule}): {self.item} {self.origin} -> {self.target}; seen by {who}"


def night(
    morning: Morning,
    first: Morning,
    spots: Sequence[str],
    people: Sequence[str],
    goals: Sequence[str],
    seed: int,
    day: int,
) -> tuple[Morning, list[Change]]:
    """The morning of day ``day`` after the night before it: the day before's end ``morning``,
    its favourites drifted and the night's changes made (``first``: the household's first
    morning, where items rest when tidy; ``spots``: the item locations; ``people``: who may
    tidy or go out; ``goals``: what a favourite may be)."""
    rng = np.random.default_rng([seed, day, 7])
    items, beliefs = dict(morning.items), {p: dict(b) for p, b in morning.beliefs.items()}
    changes: list[Change] = []

    def move(rule: str, item: str, target: str, mover: str | None) -> None:
        changes.append(Change(rule, item, items[item], target, (mover,) if mover else ()))
        items[item] = target
        if mover is not None:
            beliefs.setdefault(mover, {})[item] = target

    names = sorted(items)
    if rng.random() < TIDY:
        untidy = [i for i in names if first.items.get(i, items[i]) != items[i]]
        if untidy:
            item = untidy[int(rng.integers(len(untidy)))]
            move("tidy", item, first.items[item], people[int(rng.integers(len(people)))])
    for rule, chance, by_someone in (("visitor", VISITOR, False), ("out and back", OUT_AND_BACK, True)):
        if rng.random() < chance and len(spots) > 1:
            item = names[int(rng.integers(len(names)))]
            others = [s for s in spots if s != items[item]]
            mover = people[int(rng.integers(len(people)))] if by_someone else None
            move(rule, item, others[int(rng.integers(len(others)))], mover)
    favourites = drift(morning.favourites, goals, rng)
    return Morning(items=items, beliefs=beliefs, favourites=favourites), changes


def drift(favourites: dict[str, str], goals: Sequence[str], rng: np.random.Generator) -> dict[str, str]:
    """Each favourite redrawn with chance :data:`DRIFT`, uniformly among the other ``goals``."""
    drifted = {}
    for person in sorted(favourites):
        wanted = favourites[person]
        others = [g for g in goals if g != wanted]
        if rng.random() < DRIFT and others:
            wanted = others[int(rng.integers(len(others)))]
        drifted[person] = wanted
    return drifted


def household_lines(household: str, day: int, changes: Sequence[Change] = ()) -> list[str]:
    """The ``[household]`` table of day ``day`` (with the night's changes as comments)."""
    return [*(c.comment() for c in changes), "[household]", f'id = "{household}"', f"day = {day}", ""]
