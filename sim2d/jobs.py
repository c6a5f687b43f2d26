"""A task episode's first jobs for an autonomous person (``[[agents]]`` keys ``errand``,
``errand_after``, ``move``, ``move_after`` and ``knows``), read and checked."""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

from .errors import ScenarioError
from .maps import GameMap


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

    @property
    def any(self) -> bool:
        return bool(self.errand or self.errand_after or self.moves or self.move_after or self.knows)


def parse_jobs(table: dict[str, Any], game_map: GameMap, path: Path, entry: str) -> Jobs:
    """The jobs of one ``[[agents]]`` table (checked against the map; items are checked with
    the scenario's items, by the caller)."""
    ticks = {key: table.get(key, 0) for key in ("errand", "errand_after", "move_after")}
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
    knows = table.get("knows", [])
    if not isinstance(knows, list) or not all(isinstance(k, str) for k in knows):
        raise ScenarioError(path, entry, f"expected knows = [item, ...], got {knows!r}")
    return Jobs(
        errand=ticks["errand"],
        errand_after=ticks["errand_after"],
        moves=(moves[0], moves[1]) if moves is not None else None,
        move_after=ticks["move_after"],
        knows=tuple(knows),
    )


def job_items(jobs: Jobs) -> list[tuple[str, str]]:
    """``(key, item)`` for every item the jobs name (to check against the scenario's items)."""
    return [*((("move", jobs.moves[0]),) if jobs.moves else ()), *(("knows", k) for k in jobs.knows)]
