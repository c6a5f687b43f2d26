"""What ``toyroom memory show`` prints: one row per household, day and person, with places and
items named as the scene names them (``S1 in Storage 1``), chosen by person, household, and
the latest day only (what the next day starts from)."""

from __future__ import annotations

import time
from pathlib import Path

from rich.table import Table

from ..errors import MemoryRequestError
from .snapshot import Distribution, Snapshot


def chosen(
    saved: list[tuple[Snapshot, float]],
    person: str | None = None,
    household: str | None = None,
    latest: bool = False,
    where: str = "the memory",
) -> list[tuple[Snapshot, float]]:
    """The snapshots of ``household`` (``None``: every one) that hold ``person`` (``None``:
    anyone), only each household's latest with ``latest``.

    Raises:
        MemoryRequestError: nothing is left: naming what the file holds.
    """
    homes = sorted({s.household for s, _ in saved})
    if household is not None and household not in homes:
        raise MemoryRequestError(
            f"{where} holds no household {household!r} (it holds {', '.join(homes) or 'none'})"
        )
    out = [(s, t) for s, t in saved if household in (None, s.household)]
    if person is not None:
        everyone = sorted({p.person for s, _ in out for p in s.people})
        out = [(s, t) for s, t in out if s.person(person) is not None]
        if not out:
            there = f" in household {household!r}" if household is not None else ""
            raise MemoryRequestError(
                f"{where} holds no person {person!r}{there} (it holds {', '.join(everyone) or 'no one'})"
            )
    if latest:
        last = {s.household: (s, t) for s, t in out}  # by household, day, kind: the last wins
        out = list(last.values())
    return out


def table(
    saved: list[tuple[Snapshot, float]],
    path: Path,
    names: dict[str, dict[str, str]],
    person: str | None = None,
) -> Table:
    """One row per household, day (end or checkpoint) and person (only ``person``)."""
    out = Table(title=f"memory {path}")
    for column in ("household", "day", "saved (UTC)", "tick", "person", "favourite", "believes"):
        out.add_column(column)
    for s, saved_at in saved:
        named = names.get(s.household, {})
        day = f"{s.day}" if s.final else f"{s.day} (checkpoint)"
        when = time.strftime("%Y-%m-%d %H:%M", time.gmtime(saved_at))
        for p in s.people:
            if person is not None and p.person != person:
                continue
            believes = ", ".join(
                f"{named.get(item, item)} at {_top(where, named)}"
                for item, where in sorted(p.beliefs.items())
            )
            out.add_row(s.household, day, when, str(s.tick), p.person, _top(p.preference, named), believes)
    return out


def _top(distribution: Distribution, names: dict[str, str]) -> str:
    """The likeliest entry, as the scene names it, and its probability: ``S1 in Storage 1 0.93``."""
    if not distribution:
        return "-"
    best = max(sorted(distribution), key=lambda k: distribution[k])
    return f"{names.get(best, best)} {distribution[best]:.2f}"
