"""The brain's memory of each household across days (round 4): what it read of each person
(desires, beliefs) and where it believes each item rests, kept in an embedded SQLite file
(:mod:`.store`), and the next day's priors read from it (:mod:`.priors`)."""

from .keeper import CHECKPOINT_TICKS, MemoryKeeper
from .priors import desire_prior, remembered, remembered_beliefs, view_log_prior
from .snapshot import PersonMemory, Snapshot, snapshot_of
from .store import KEEP_DAYS, SCHEMA_VERSION, MemoryStore, open_memory

__all__ = [
    "CHECKPOINT_TICKS",
    "KEEP_DAYS",
    "MemoryKeeper",
    "SCHEMA_VERSION",
    "MemoryStore",
    "PersonMemory",
    "Snapshot",
    "desire_prior",
    "open_memory",
    "remembered",
    "remembered_beliefs",
    "snapshot_of",
    "view_log_prior",
]
