"""The brain's memory of each household, kept across days in an embedded SQLite file.

One file holds many households. Each :meth:`MemoryStore.save` is one transaction: a day's
end (``final``), or a checkpoint within a day, which replaces that day's earlier checkpoint.
A day starts from the last day's end before it (:meth:`MemoryStore.morning`), or from that
day's last checkpoint when its brain stopped before the day ended (the brain warns, naming the
day); a brain that restarts in the middle of a day resumes from that day's last checkpoint
(:meth:`MemoryStore.resume`), so it loses at most what it learned since then.

Each day saved carries its clock time (``saved_at``, seconds since 1970 UTC). Every save
prunes the history older than the store's ``keep_days`` (:data:`KEEP_DAYS` by default), except
what tomorrow needs: each household's latest day, whatever its age. Deleted rows' bytes are
zeroed (``secure_delete``).

Opening the file, and the files it refuses: :mod:`.opening`.
"""

from __future__ import annotations

import sqlite3
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from pathlib import Path

from ..errors import MemoryRequestError
from .opening import LOCK_SECONDS, SCHEMA_VERSION, connect
from .snapshot import Distribution, PersonMemory, Snapshot

TABLES = ("days", "preferences", "beliefs", "items")
PERSON_TABLES = ("preferences", "beliefs")
KEEP_DAYS = 30.0
"""How many days (of the clock) of history a save keeps by default (``--keep-days``); each
household's latest day is kept whatever its age: the next day starts from it."""
DAY_SECONDS = 86400.0

__all__ = ["KEEP_DAYS", "SCHEMA_VERSION", "MemoryStore", "open_memory"]


class MemoryStore:
    """An open memory file (:func:`open_memory`); a context manager that closes it."""

    def __init__(
        self,
        path: Path,
        connection: sqlite3.Connection,
        keep_days: float = KEEP_DAYS,
        clock: Callable[[], float] = time.time,
    ) -> None:
        if not keep_days >= 0:
            raise ValueError(f"keep_days is a number of days >= 0, not {keep_days}")
        self.path = path
        self.keep_days = keep_days
        self.clock = clock
        """Seconds since 1970 UTC, for each save's ``saved_at`` (a test sets its own)."""
        self._db = connection

    def __enter__(self) -> MemoryStore:
        return self

    def __exit__(self, *_: object) -> None:
        self.close()

    def close(self) -> None:
        self._db.close()

    @contextmanager
    def _transaction(self) -> Iterator[sqlite3.Connection]:
        self._db.execute("BEGIN IMMEDIATE")
        try:
            yield self._db
        except BaseException:
            self._db.execute("ROLLBACK")
            raise
        self._db.execute("COMMIT")

    # ----- writing ------------------------------------------------------------------------

    def save(self, snapshot: Snapshot) -> None:
        """Write ``snapshot`` in one transaction, replacing what the file held for the same
        household, day and kind (end of day, or checkpoint); a day's end also drops that
        day's checkpoint. The history older than ``keep_days`` goes in the same transaction
        (each household's latest day stays)."""
        now = self.clock()
        with self._transaction() as db:
            self._write(db, snapshot, now)
            self._prune(db, now - self.keep_days * DAY_SECONDS)

    def restore(self, saved: list[tuple[Snapshot, float]], names: dict[str, dict[str, str]]) -> None:
        """Write each snapshot with the clock time it was saved at, and the names of places
        and items by household, in one transaction, pruning nothing (``toyroom memory
        import``)."""
        with self._transaction() as db:
            for snapshot, saved_at in saved:
                self._write(db, snapshot, saved_at)
            for household, named in names.items():
                db.executemany(
                    "INSERT OR REPLACE INTO names VALUES (?, ?, ?)", [(household, *n) for n in named.items()]
                )

    def name(self, household: str, names: dict[str, str]) -> None:
        """Keep the names the scene gives ``household``'s places and items (id -> name)."""
        with self._transaction() as db:
            db.executemany(
                "INSERT OR REPLACE INTO names VALUES (?, ?, ?)", [(household, *n) for n in names.items()]
            )

    def names(self) -> dict[str, dict[str, str]]:
        """Household -> id -> the name its scene gives that place or item."""
        out: dict[str, dict[str, str]] = {}
        for home, key, name in self._db.execute("SELECT household, id, name FROM names ORDER BY 1, 2"):
            out.setdefault(home, {})[key] = name
        return out

    def _prune(self, db: sqlite3.Connection, before: float) -> None:
        """Remove each day saved before ``before`` (seconds since 1970) that is not its
        household's latest."""
        old = db.execute(
            "SELECT household, day FROM days AS d WHERE saved_at <= ? AND day < "
            "(SELECT MAX(day) FROM days WHERE household = d.household)",
            (before,),
        ).fetchall()
        for table in TABLES:
            db.executemany(f"DELETE FROM {table} WHERE household = ? AND day = ?", old)  # noqa: S608

    def _write(self, db: sqlite3.Connection, snapshot: Snapshot, saved_at: float) -> None:
        key = (snapshot.household, snapshot.day)
        for table in TABLES:
            db.execute(f"DELETE FROM {table} WHERE household = ? AND day = ?", key)  # noqa: S608
        db.execute("INSERT INTO days VALUES (?, ?, ?, ?, ?)", (*key, snapshot.final, snapshot.tick, saved_at))
        row = (*key, snapshot.final)
        db.executemany(
            "INSERT INTO preferences VALUES (?, ?, ?, ?, ?, ?)",
            [(*row, p.person, goal, q) for p in snapshot.people for goal, q in p.preference.items()],
        )
        db.executemany(
            "INSERT INTO beliefs VALUES (?, ?, ?, ?, ?, ?, ?)",
            [
                (*row, p.person, item, loc, q)
                for p in snapshot.people
                for item, where in p.beliefs.items()
                for loc, q in where.items()
            ],
        )
        db.executemany(
            "INSERT INTO items VALUES (?, ?, ?, ?, ?, ?)",
            [(*row, item, loc, q) for item, where in snapshot.items.items() for loc, q in where.items()],
        )

    def forget(self, person: str, household: str | None = None) -> int:
        """Remove every row about ``person`` in ``household`` (``None``: the one household
        that holds them), their bytes with them (``secure_delete``, then ``VACUUM``); how many.

        Raises:
            MemoryRequestError: no such person (in that household), no such household, or
                the person is in more than one household and none is named.
        """
        home = self.household_of(person, household)
        self._db.execute("PRAGMA secure_delete = ON")  # whatever the build's default, or a caller's
        with self._transaction() as db:
            removed = sum(
                db.execute(
                    f"DELETE FROM {table} WHERE household = ? AND person = ?",  # noqa: S608
                    (home, person),
                ).rowcount
                for table in PERSON_TABLES
            )
        self._db.execute("VACUUM")  # the freed pages go too, whatever the build's secure_delete
        return removed

    def household_of(self, person: str, household: str | None) -> str:
        """The household ``forget`` acts on (see :meth:`forget`)."""
        holding = self.people_by_household()
        if household is not None and household not in holding:
            raise MemoryRequestError(
                f"memory file {self.path} holds no household {household!r} "
                f"(it holds {_listed(holding) or 'none'})"
            )
        homes = [h for h, people in holding.items() if person in people]
        if household is not None:
            if household not in homes:
                raise MemoryRequestError(
                    f"memory file {self.path} holds no person {person!r} in household {household!r} "
                    f"(it holds {', '.join(holding[household]) or 'no one'} there)"
                )
            return household
        if not homes:
            everyone = sorted({p for people in holding.values() for p in people})
            raise MemoryRequestError(
                f"memory file {self.path} holds no person {person!r} "
                f"(it holds {', '.join(everyone) or 'no one'}; an id as the scene names it, case "
                "and spaces included)"
            )
        if len(homes) > 1:
            raise MemoryRequestError(
                f"person {person!r} is in {len(homes)} households of memory file {self.path} "
                f"({', '.join(homes)}): name one with --household"
            )
        return homes[0]

    # ----- reading ------------------------------------------------------------------------

    def households(self) -> list[str]:
        """Every household the file remembers, sorted."""
        return [r[0] for r in self._db.execute("SELECT DISTINCT household FROM days ORDER BY household")]

    def people_by_household(self) -> dict[str, list[str]]:
        """Every household the file remembers and the people it remembers in it, sorted."""
        out: dict[str, list[str]] = {h: [] for h in self.households()}
        query = "SELECT household, person FROM preferences UNION SELECT household, person FROM beliefs"
        for home, person in sorted(self._db.execute(query).fetchall()):
            out.setdefault(home, []).append(person)
        return out

    def people(self) -> list[str]:
        """Every person the file remembers (in any household), sorted."""
        rows = self._db.execute("SELECT DISTINCT person FROM preferences UNION SELECT person FROM beliefs")
        return sorted(r[0] for r in rows)

    def morning(self, household: str, day: int) -> Snapshot | None:
        """What day ``day`` of ``household`` starts from: the last day before it that is
        remembered, by its end, or by its last checkpoint when its brain stopped before the
        day ended (the snapshot says which: ``final``); ``None``: no day before it is
        remembered. A day's end replaces its checkpoint, so a day has one or the other."""
        row = self._db.execute(
            "SELECT day, MAX(final) FROM days WHERE household = ? AND day < ? "
            "GROUP BY day ORDER BY day DESC LIMIT 1",
            (household, day),
        ).fetchone()
        return None if row is None else self._read(household, int(row[0]), bool(row[1]))

    def resume(self, household: str, day: int) -> Snapshot | None:
        """What a brain restarted within day ``day`` resumes from: that day's last checkpoint,
        else the day's morning."""
        row = self._db.execute(
            "SELECT 1 FROM days WHERE household = ? AND day = ? AND final = 0", (household, day)
        ).fetchone()
        return self._read(household, day, False) if row else self.morning(household, day)

    def snapshots(self) -> list[Snapshot]:
        """Everything the file holds, by household, day and kind."""
        return [s for s, _ in self.saved()]

    def saved(self) -> list[tuple[Snapshot, float]]:
        """Everything the file holds, by household, day and kind, each with the clock time
        it was saved at (seconds since 1970 UTC)."""
        rows = self._db.execute(
            "SELECT household, day, final, saved_at FROM days ORDER BY household, day, final"
        )
        return [(self._read(h, d, bool(f)), float(t)) for h, d, f, t in rows.fetchall()]

    def _read(self, household: str, day: int, final: bool) -> Snapshot:
        key = (household, day, final)
        (tick,) = self._db.execute(
            "SELECT tick FROM days WHERE household = ? AND day = ? AND final = ?", key
        ).fetchone()
        where = "WHERE household = ? AND day = ? AND final = ?"
        preference: dict[str, Distribution] = {}
        for person, goal, p in self._db.execute(f"SELECT person, goal, p FROM preferences {where}", key):
            preference.setdefault(person, {})[goal] = p
        beliefs: dict[str, dict[str, Distribution]] = {}
        query = f"SELECT person, item, location, p FROM beliefs {where}"
        for person, item, loc, p in self._db.execute(query, key):
            beliefs.setdefault(person, {}).setdefault(item, {})[loc] = p
        items: dict[str, Distribution] = {}
        for item, loc, p in self._db.execute(f"SELECT item, location, p FROM items {where}", key):
            items.setdefault(item, {})[loc] = p
        people = tuple(
            PersonMemory(person, preference.get(person, {}), beliefs.get(person, {}))
            for person in sorted(set(preference) | set(beliefs))
        )
        return Snapshot(household, day, tick, final, people, items)


def open_memory(
    path: Path, *, read_only: bool = False, keep_days: float = KEEP_DAYS, wait: float = LOCK_SECONDS
) -> MemoryStore:
    """Open (or create) the memory file at ``path`` and hold it for this process
    (``read_only``: an existing file, for reading only: nothing is written to it, not even a
    schema); its saves keep ``keep_days`` days of history (:meth:`MemoryStore.save`); ``wait``:
    seconds to wait for another process to let the file go (0: a probe that never holds up
    the one that has it).

    Raises:
        MemoryFileError: not a toyroom memory, damaged, newer, held by another process
            (:class:`~brain.errors.MemoryInUseError`), or (not ``read_only``) a file this
            process cannot write.
    """
    path = Path(path)
    return MemoryStore(path, connect(path, read_only=read_only, wait=wait), keep_days)


def _listed(holding: dict[str, list[str]]) -> str:
    return ", ".join(f"{h} ({', '.join(people) or 'no one'})" for h, people in holding.items())
