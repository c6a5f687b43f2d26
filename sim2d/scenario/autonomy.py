"""How autonomous people behave: a scenario's ``[autonomy]`` table, read and checked (the
people themselves are :mod:`sim2d.people.autonomous` and :mod:`sim2d.people.planned`)."""

from __future__ import annotations

import logging
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..errors import ScenarioError
from .tables import check_keys

RATES = (
    "switch",
    "mischief",
    "put_away",
    "forget_per_tick",
    "miss",
    "hearsay_per_tick",
    "wander",
    "replan",
    "knows",
    "stale",
    "silent",
)
"""The probabilities of :class:`Autonomy`."""
RENAMED = {"forget": "forget_per_tick", "hearsay": "hearsay_per_tick"}
"""Former keys of ``[autonomy]``, each read as its new key with a warning, so episodes
written before a rename keep working."""
SEARCH_ORDERS = ("likely", "nearest")
PLANNERS = ("own", "model")
AUTONOMY_KEYS = frozenset({*RATES, "play_ticks", "wait_ticks", "replan_lag", "search", "planner"})
"""The keys of ``[autonomy]``."""


@dataclass(frozen=True)
class Autonomy:
    """How autonomous people behave. Probabilities per tick; durations in ticks (min, max)."""

    switch: float = 0.002
    """Chance per tick that the preference changes."""
    mischief: float = 0.05
    """Chance, when deciding with empty hands, of moving an item that is not one's wish."""
    put_away: float = 0.5
    """Chance of putting an item away (and wanting something else) after playing with it."""
    play_ticks: tuple[int, int] = (60, 200)
    wait_ticks: tuple[int, int] = (20, 60)
    forget_per_tick: float = 0.0
    """Rate per tick at which the belief about an item out of view drifts toward uniform
    over the locations: ``p <- (1 - forget_per_tick) p + forget_per_tick / L`` each tick
    (formerly ``forget``)."""
    miss: float = 0.0
    """Chance that an item coming into view (at a location, not carried by the person) goes
    unnoticed for as long as it stays in view there: its belief is left as it was."""
    hearsay_per_tick: float = 0.0
    """Chance per tick, for two autonomous people in one region, that one tells the other
    where they believe an item is (one they disagree on), unheard by the robot (formerly
    ``hearsay``; the brain's ``hearsay_per_s`` is the same rule per second:
    ``-ln(1 - hearsay_per_tick) / tick_seconds``)."""
    search: str = "likely"
    """Where a person looks for what they want: ``likely`` (the most probable place; ties:
    the first) or ``nearest`` (the nearest place at least half as probable as the best)."""
    wander: float = 0.0
    """Chance, when setting off for what they want, of first walking to a random cell."""
    replan: float = 0.0
    """Chance per tick of dropping a walk under way and deciding again."""
    replan_lag: tuple[int, int] = (2, 8)
    """Ticks from a change of belief that makes a walk pointless (the item they are after seen
    elsewhere, or gone from where they are heading) to deciding again: drawn once per person,
    the first time it is needed (people who never need it draw nothing)."""
    knows: float = 0.0
    """Chance, per person and item, of starting sure of where the item is."""
    stale: float = 0.0
    """Chance, per person and item, of starting sure the item is at another of the item
    locations (drawn uniformly): a false belief from before the episode. Otherwise (and at
    ``knows = stale = 0``) a person starts not knowing: uniform over the locations."""
    silent: float = 0.0
    """Chance that a person who is busy (carrying something, playing, or on an errand) does
    not answer a robot's question (``ask``) at all; free, they always answer, truthfully."""
    planner: str = "own"
    """``own`` habits (:mod:`sim2d.people.autonomous`) or the brain's planner (``model``:
    :mod:`sim2d.people.planned`)."""

    def __post_init__(self) -> None:
        rates = {name: getattr(self, name) for name in RATES}
        bad = [f"{name} = {value}" for name, value in rates.items() if not 0.0 <= value <= 1.0]
        if bad:
            raise ValueError(f"probabilities must be in [0, 1]: {', '.join(bad)}")
        if self.knows + self.stale > 1.0:
            raise ValueError(f"knows + stale must be at most 1, not {self.knows} + {self.stale}")
        for name, known in (("search", SEARCH_ORDERS), ("planner", PLANNERS)):
            if getattr(self, name) not in known:
                raise ValueError(f"{name} must be one of {', '.join(known)}, not {getattr(self, name)!r}")


def _tick_range(value: Any, default: tuple[int, int]) -> tuple[int, int]:
    """``[min, max]`` ticks, two integers (``5.9`` is refused, not read as 5)."""
    low, high = value if value is not None else default
    if not all(isinstance(v, int) and not isinstance(v, bool) for v in (low, high)):
        raise ValueError(f"a tick pair must be two integers, got {value!r}")
    return (low, high)


def _rate(table: dict[str, Any], name: str) -> float:
    """A probability of the table: a number (``true`` or ``"0.5"`` is refused)."""
    value = table[name]
    if not isinstance(value, int | float) or isinstance(value, bool):
        raise ValueError(f"{name} must be a number, got {value!r}")
    return float(value)


log = logging.getLogger(__name__)


def current_key(name: str) -> str:
    """``name``, or the new key of an ``[autonomy]`` key :data:`RENAMED` (with a one-line
    warning)."""
    new = RENAMED.get(name)
    if new is None:
        return name
    log.warning("autonomy setting %r is now called %r: please use the new name", name, new)
    return new


def _renamed(table: Any, path: Path) -> Any:
    """``table`` (an ``[autonomy]`` table, when it is one) with former keys read as new ones.

    Raises:
        ScenarioError: a key set twice, by its name and a former one."""
    if not isinstance(table, dict) or not RENAMED.keys() & table.keys():
        return table
    out: dict[str, Any] = {}
    for name, value in table.items():
        key = current_key(name)
        if key in out:
            raise ScenarioError(path, "autonomy", f"{key} is set twice (once by its former name)")
        out[key] = value
    return out


def parse_autonomy(data: dict[str, Any], path: Path) -> Autonomy:
    """How autonomous people behave (a scenario's ``[autonomy]``; defaults when absent).

    Raises:
        ScenarioError: an unknown key, a probability outside [0, 1], a malformed tick pair...
    """
    table = check_keys(_renamed(data.get("autonomy", {}), path), AUTONOMY_KEYS, path, "autonomy")
    try:
        return Autonomy(
            **{name: _rate(table, name) for name in RATES if name in table},
            search=str(table.get("search", Autonomy.search)),
            planner=str(table.get("planner", Autonomy.planner)),
            play_ticks=_tick_range(table.get("play_ticks"), Autonomy.play_ticks),
            wait_ticks=_tick_range(table.get("wait_ticks"), Autonomy.wait_ticks),
            replan_lag=_tick_range(table.get("replan_lag"), Autonomy.replan_lag),
        )
    except (TypeError, ValueError) as err:
        raise ScenarioError(path, "autonomy", f"expected numbers and [min, max] tick pairs ({err})") from None
