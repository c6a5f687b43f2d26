"""The node's side of the memory: which snapshot a day starts from, and when to save one.

A scene that names its household (``Scene.household``, protocol 1.5) is a day of it: the
brain starts from the end of the day before (a day's first tick), or from the day's last
checkpoint (a brain that joins the day later: restarted after a crash). It saves a checkpoint
every ``checkpoint_ticks`` engine ticks and the day's end when the episode ends, each in one
transaction (:class:`~brain.memory.store.MemoryStore`). A scene without a household uses no
memory.
"""

from __future__ import annotations

import logging

from protocol import Mind, Scene

from .snapshot import Distribution, Snapshot, snapshot_of
from .store import MemoryStore

log = logging.getLogger("toyroom.brain")

CHECKPOINT_TICKS = 100
"""Engine ticks between two checkpoints within a day (the default)."""


class MemoryKeeper:
    """Reads and saves one brain's memory (``store``, held open for the brain's life)."""

    def __init__(self, store: MemoryStore, checkpoint_ticks: int = CHECKPOINT_TICKS) -> None:
        if checkpoint_ticks < 1:
            raise ValueError(f"checkpoint_ticks is a number of ticks >= 1, not {checkpoint_ticks}")
        self.store = store
        self.checkpoint_ticks = checkpoint_ticks
        self.household: tuple[str, int] | None = None
        """The (household, day) being followed (``None``: the scene names none)."""
        self._saved_at: int | None = None

    def start(self, scene: Scene, tick: int | None) -> Snapshot | None:
        """What the day of ``scene`` starts from, joined at engine tick ``tick`` (``None``:
        not known yet: the day's checkpoint if any)."""
        if scene.household is None:
            self.household = None
            log.info("scene '%s' names no household: the memory is not used", scene.name)
            return None
        key = self.household = (scene.household.id, scene.household.day)
        self._saved_at = tick
        memory = self.store.morning(*key) if tick == 0 else self.store.resume(*key)
        if memory is None:
            log.info("household '%s' day %d: nothing remembered before it", *key)
        else:
            kind = "end" if memory.final else f"checkpoint at tick {memory.tick}"
            log.info("household '%s' day %d: starting from day %d's %s", *key, memory.day, kind)
        return memory

    def after_tick(self, mind: Mind, items: dict[str, Distribution], over: bool) -> None:
        """Save the day's end when ``over``, else a checkpoint when one is due."""
        if self.household is None:
            return
        due = self._saved_at is None or mind.tick - self._saved_at >= self.checkpoint_ticks
        if over or due:
            self.store.save(snapshot_of(*self.household, mind, items, final=over))
            self._saved_at = mind.tick
