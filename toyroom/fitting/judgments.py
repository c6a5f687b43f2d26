"""Ratings people gave about recorded episodes (``toyroom fit --judgments FILE.csv``), read
and checked against the recordings.

The file has a header and the columns ``episode, tick, person, quantity, target, value``,
and optionally ``estimate`` (other columns, such as a rating page's ``participant`` and
``question``, are read past):

- ``episode``: a recording, by its file name without the extension or by its scenario name;
- ``tick``: the engine tick the rating is about (the brain's estimate after it);
- ``person``: a person of that recording's scene;
- ``quantity`` and ``target``: ``belief`` with ``ITEM@LOCATION`` (how likely the person
  thinks the item is there), ``desire`` with a goal (an item, or ``out``: how likely it is
  what they want most), ``utility`` with a goal (how much they want it), ``rank`` with a
  goal (its place among the goals, 1 the most wanted), ``false_belief`` with an item (how
  likely their belief about it is false);
- ``value``: the rating, any number (only its correlation with the brain's estimates counts);
- ``estimate``: ``online`` (the default, also when empty: the estimate from what was seen up
  to ``tick``) or ``smoothed`` (retrospective: the estimate at ``tick`` given the whole
  episode, as a question answered after watching all of it).

Several ratings of one question (the same episode, tick, person, quantity, target and
estimate: several raters) are averaged into one judgment. How each quantity is read off the
brain's estimates: :mod:`toyroom.fitting.judged`.
"""

from __future__ import annotations

import csv
import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from brain.errors import SettingsError
from bridge.recording.trace import Trace
from protocol import AgentKind

COLUMNS = ("episode", "tick", "person", "quantity", "target", "value")
QUANTITIES = ("belief", "desire", "utility", "rank", "false_belief")
GOAL_QUANTITIES = ("desire", "utility", "rank")
"""The quantities whose target is a goal (an item, or ``out``)."""
ESTIMATES = ("online", "smoothed")
OUT = "out"


class JudgmentsError(SettingsError):
    """A judgments file that cannot be read, or that names what the recordings do not have."""


@dataclass(frozen=True)
class Judgment:
    """One rating (or the mean of several raters' of one question), resolved: the
    recording's index, the person, and the estimate's entry (``index``: ``(item, location)``
    for a belief, ``(goal,)`` for a desire, utility or rank, ``(item,)`` for a false belief),
    of the ``online`` or ``smoothed`` estimate."""

    line: int
    episode: int
    tick: int
    person: str
    quantity: str
    index: tuple[int, ...]
    value: float
    estimate: str = "online"

    @property
    def kind(self) -> str:
        """What the rating is compared as: the quantity, ``smoothed `` before it for a
        retrospective one (each kind has its own correlation)."""
        return self.quantity if self.estimate == "online" else f"smoothed {self.quantity}"


def load_judgments(path: Path, traces: Sequence[Trace], names: Sequence[str]) -> list[Judgment]:
    """Read ``path`` against the recordings (``names``: each one's file name without extension).

    Raises:
        JudgmentsError: naming the file, the line and what is wrong."""
    try:
        with path.open(newline="", encoding="utf-8") as handle:
            rows = list(csv.DictReader(handle))
            header = tuple(rows[0].keys()) if rows else ()
    except (OSError, UnicodeDecodeError, csv.Error) as err:
        raise JudgmentsError(f"{path}: cannot read the judgments ({err})") from None
    missing = [c for c in COLUMNS if c not in header]
    if not rows or missing:
        raise JudgmentsError(
            f"{path}: expected a header with {', '.join(COLUMNS)} and rows; missing {missing}"
        )
    episodes = _episode_names(traces, names)
    return merge_raters([_judgment(path, n, row, traces, episodes) for n, row in enumerate(rows, start=2)])


def rating_counts(path: Path) -> dict[str, int]:
    """How many ratings (rows), raters (distinct ``participant``; 0 when the file has no such
    column) and rated recordings (distinct ``episode``) a judgments file holds."""
    with path.open(newline="", encoding="utf-8") as handle:
        rows = list(csv.DictReader(handle))
    raters = {row["participant"] for row in rows if row.get("participant")}
    return {"ratings": len(rows), "raters": len(raters), "episodes": len({row["episode"] for row in rows})}


def merge_raters(judgments: Sequence[Judgment]) -> list[Judgment]:
    """One judgment per question (episode, tick, person, quantity, entry, estimate): the mean
    of its ratings, at the first one's line, in the order questions first appear."""
    groups: dict[tuple[object, ...], list[Judgment]] = {}
    for j in judgments:
        groups.setdefault((j.episode, j.tick, j.person, j.quantity, j.index, j.estimate), []).append(j)
    return [
        dataclasses.replace(js[0], value=float(np.mean([j.value for j in js]))) if len(js) > 1 else js[0]
        for js in groups.values()
    ]


def _episode_names(traces: Sequence[Trace], names: Sequence[str]) -> dict[str, int]:
    """Each recording by file name and by scenario name, where the name is one recording's only."""
    found: dict[str, set[int]] = {}
    for e, (trace, name) in enumerate(zip(traces, names, strict=True)):
        found.setdefault(trace.info.scenario, set()).add(e)
        found.setdefault(name, set()).add(e)
    return {name: next(iter(e)) for name, e in found.items() if len(e) == 1}


def _judgment(
    path: Path, line: int, row: dict[str, str], traces: Sequence[Trace], episodes: dict[str, int]
) -> Judgment:
    def bad(what: str) -> JudgmentsError:
        return JudgmentsError(f"{path} line {line}: {what}")

    name = (row["episode"] or "").strip()
    if name not in episodes:
        raise bad(f"episode {name!r} is no recording given (known: {', '.join(sorted(episodes))})")
    e = episodes[name]
    scene = traces[e].info.scene
    people = [a.id for a in scene.agents if a.kind is AgentKind.PERSON]
    items, locations = [i.id for i in scene.items], [loc.id for loc in scene.locations]
    person, quantity, target = (row[c].strip() for c in ("person", "quantity", "target"))
    if person not in people:
        raise bad(f"person {person!r} is not in episode {name} (people: {', '.join(people)})")
    try:
        tick, value = int(row["tick"]), float(row["value"])
    except (TypeError, ValueError):
        raise bad(
            f"tick must be an integer and value a number, got {row['tick']!r} and {row['value']!r}"
        ) from None
    last = traces[e].ticks[-1][0].tick if traces[e].ticks else 0
    if not 0 <= tick <= last:
        raise bad(f"tick {tick} is outside episode {name} (ticks 0 to {last})")
    if quantity not in QUANTITIES:
        raise bad(f"quantity {quantity!r} is unknown (known: {', '.join(QUANTITIES)})")
    estimate = (row.get("estimate") or "").strip() or "online"
    if estimate not in ESTIMATES:
        raise bad(f"estimate {estimate!r} is unknown (known: {', '.join(ESTIMATES)})")
    item, _, location = target.partition("@")
    if quantity in GOAL_QUANTITIES:
        if target not in (*items, OUT):
            raise bad(f"goal {target!r} is unknown (goals: {', '.join([*items, OUT])})")
        index: tuple[int, ...] = ((items + [OUT]).index(target),)
    elif item not in items:
        raise bad(f"item {item!r} is unknown (items: {', '.join(items)})")
    elif quantity == "belief":
        if location not in locations:
            raise bad(
                f"a belief's target is ITEM@LOCATION; location {location!r} is unknown "
                f"({', '.join(locations)})"
            )
        index = (items.index(item), locations.index(location))
    else:
        index = (items.index(item),)
    return Judgment(line, e, tick, person, quantity, index, value, estimate)
