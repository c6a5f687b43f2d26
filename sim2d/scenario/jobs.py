"""A task episode's first jobs for an autonomous person (``[[agents]]`` keys ``errand``,
``errand_after``, ``move``, ``move_after``, ``wait``, ``tell``, ``tell_after``, ``knows``,
``believes`` and ``overlooks``), read and checked."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from ..errors import ScenarioError
from .maps import GameMap

JOB_KEYS = "task jobs (errand, move, wait, tell, knows, believes, overlooks)"
"""How errors name the keys of a task episode's jobs."""


@dataclass(frozen=True)
class Jobs:
    """What an autonomous person does first, and knows from the start (all off by default)."""

    errand: int = 0
    """An errand first: this many ticks outside before anything else."""
    errand_after: int = 0
    """Ticks the person stays where they are (watching) before the errand."""
    moves: tuple[str, str] | None = None
    """A first job: move this item to this location (``move = [item, loc]``)."""
    move_after: int = 0
    """Ticks the person waits where they are before that move."""
    knows: tuple[str, ...] = ()
    """Items whose place the person knows at the start, whatever the episode's ``knows`` and
    ``stale`` draw (a task's owner knows where they left their item)."""
    wait: int = 0
    """Ticks the person stands where they are before anything else (talking, say)."""
    tells: tuple[str, str] | None = None
    """``(person, item)``: tell that person where this one believes ``item`` is, once, when
    both are in one region (``tell = [person, item]``); unheard by the robot, as hearsay is."""
    tell_after: int = 0
    """The tick from which the telling happens."""
    believes: tuple[tuple[str, str], ...] = ()
    """``(item, location)``: sure at the start that ``item`` is there, whatever the truth
    (``believes = [[item, location], ...]``: a belief from before the episode)."""
    overlooks: tuple[str, ...] = ()
    """Items the person fails to notice wherever they see them, from the start until they
    stand at the place they believe the item is (where they look closely)."""

    @property
    def any(self) -> bool:
        return bool(
            self.errand
            or self.errand_after
            or self.moves
            or self.move_after
            or self.knows
            or self.wait
            or self.tells
            or self.believes
            or self.overlooks
        )


def parse_jobs(table: dict[str, Any], game_map: GameMap, path: Path, entry: str) -> Jobs:
    """The jobs of one ``[[agents]]`` table (checked against the map; items are checked with
    the scenario's items, by the caller)."""
    ticks = {key: table.get(key, 0) for key in ("errand", "errand_after", "move_after", "wait", "tell_after")}
    for key, value in ticks.items():
        if not isinstance(value, int) or isinstance(value, bool) or value < 0:
            raise ScenarioError(path, entry, f"expected {key} = a number of ticks >= 0, got {value!r}")
    moves = table.get("move")
    if moves is not None and not (
        isinstance(moves, list) and len(moves) == 2 and all(isinstance(m, str) for m in moves)
    ):
        raise ScenarioError(path, entry, f"expected move = [item, location], got {moves!r}")
    if moves is not None and moves[1] not in {loc.id for loc in game_map.locations}:
        raise ScenarioError(path, entry, f"move: unknown location {moves[1]!r}")
    knows, overlooks = _names(table, "knows", path, entry), _names(table, "overlooks", path, entry)
    tells = _pair(table, "tell", "[person, item]", path, entry)
    believes = table.get("believes", [])
    if not isinstance(believes, list) or not all(_is_pair(b) for b in believes):
        raise ScenarioError(path, entry, f"expected believes = [[item, location], ...], got {believes!r}")
    unknown = [loc for _, loc in believes if loc not in {loc.id for loc in game_map.locations}]
    if unknown:
        raise ScenarioError(path, entry, f"believes: unknown location {unknown[0]!r}")
    return Jobs(
        errand=ticks["errand"],
        errand_after=ticks["errand_after"],
        moves=(moves[0], moves[1]) if moves is not None else None,
        move_after=ticks["move_after"],
        knows=knows,
        wait=ticks["wait"],
        tells=tells,
        tell_after=ticks["tell_after"],
        believes=tuple((item, loc) for item, loc in believes),
        overlooks=overlooks,
    )


def _is_pair(value: Any) -> bool:
    return isinstance(value, list) and len(value) == 2 and all(isinstance(v, str) for v in value)


def _pair(table: dict[str, Any], key: str, shape: str, path: Path, entry: str) -> tuple[str, str] | None:
    """``table[key]``, a list of two strings, or ``None`` when absent."""
    value = table.get(key)
    if value is None:
        return None
    if not _is_pair(value):
        raise ScenarioError(path, entry, f"expected {key} = {shape}, got {value!r}")
    return (value[0], value[1])


def _names(table: dict[str, Any], key: str, path: Path, entry: str) -> tuple[str, ...]:
    """``table[key]``, a list of item names (empty when absent)."""
    value = table.get(key, [])
    if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
        raise ScenarioError(path, entry, f"expected {key} = [item, ...], got {value!r}")
    return tuple(value)


def job_items(jobs: Jobs) -> list[tuple[str, str]]:
    """``(key, item)`` for every item the jobs name (to check against the scenario's items)."""
    return [
        *((("move", jobs.moves[0]),) if jobs.moves else ()),
        *((("tell", jobs.tells[1]),) if jobs.tells else ()),
        *(("knows", k) for k in jobs.knows),
        *(("believes", item) for item, _ in jobs.believes),
        *(("overlooks", k) for k in jobs.overlooks),
    ]
