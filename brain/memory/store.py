"""The brain's memory of each household, kept across days in an embedded SQLite file.

One file holds many households. Each :meth:`MemoryStore.save` is one transaction: a day's
end (``final``), or a checkpoint within a day, which replaces that day's earlier checkpoint.
A day starts from the last day's end before it (:meth:`MemoryStore.morning`); a brain that
restarts in the middle of a day resumes from that day's last checkpoint
(:meth:`MemoryStore.resume`), so it loses at most what it learned since then.

The file is refused, with a :class:`~brain.errors.MemoryFileError` naming it, when it is not
a toyroom memory (another SQLite file, or damaged bytes), when a newer toyroom wrote it (a
schema version above :data:`SCHEMA_VERSION`), or when another process holds it (a brain holds
its memory file for as long as it runs). An older schema is migrated in place.
"""

from __future__ import annotations

import json
import sqlite3
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import msgspec

from ..errors import MemoryFileError
from .snapshot import Distribution, PersonMemory, Snapshot

APPLICATION_ID = 0x746F7972
"""``PRAGMA application_id`` of a toyroom memory file ("toyr"): another SQLite file has 0."""
SCHEMA_VERSION = 1
"""The schema this toyroom writes (``PRAGMA user_version``)."""
LOCK_SECONDS = 0.5
"""How long opening waits for another process to let the file go before refusing it."""

MIGRATIONS: dict[int, str] = {
    0: """
    CREATE TABLE days (
        household TEXT NOT NULL, day INTEGER NOT NULL, final INTEGER NOT NULL,
        tick INTEGER NOT NULL, PRIMARY KEY (household, day, final));
    CREATE TABLE preferences (
        household TEXT NOT NULL, day INTEGER NOT NULL, final INTEGER NOT NULL,
        person TEXT NOT NULL, goal TEXT NOT NULL, p REAL NOT NULL,
        PRIMARY KEY (household, day, final, person, goal));
    CREATE TABLE beliefs (
        household TEXT NOT NULL, day INTEGER NOT NULL, final INTEGER NOT NULL,
        person TEXT NOT NULL, item TEXT NOT NULL, location TEXT NOT NULL, p REAL NOT NULL,
        PRIMARY KEY (household, day, final, person, item, location));
    CREATE TABLE items (
        household TEXT NOT NULL, day INTEGER NOT NULL, final INTEGER NOT NULL,
        item TEXT NOT NULL, location TEXT NOT NULL, p REAL NOT NULL,
        PRIMARY KEY (household, day, final, item, location));
    """,
}
"""SQL that takes a file from schema ``v`` to ``v + 1`` (0: an empty file)."""

TABLES = ("days", "preferences", "beliefs", "items")
PERSON_TABLES = ("preferences", "beliefs")


class MemoryStore:
    """An open memory file (:func:`open_memory`); a context manager that closes it."""

    def __init__(self, path: Path, connection: sqlite3.Connection) -> None:
        self.path = path
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
        day's checkpoint."""
        key = (snapshot.household, snapshot.day)
        with self._transaction() as db:
            for table in TABLES:
                db.execute(f"DELETE FROM {table} WHERE household = ? AND day = ?", key)  # noqa: S608
            db.execute("INSERT INTO days VALUES (?, ?, ?, ?)", (*key, snapshot.final, snapshot.tick))
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

    def forget(self, person: str) -> int:
        """Remove every row about ``person`` (in every household and day); how many."""
        with self._transaction() as db:
            return sum(
                db.execute(f"DELETE FROM {table} WHERE person = ?", (person,)).rowcount  # noqa: S608
                for table in PERSON_TABLES
            )

    # ----- reading ------------------------------------------------------------------------

    def households(self) -> list[str]:
        """Every household the file remembers, sorted."""
        return [r[0] for r in self._db.execute("SELECT DISTINCT household FROM days ORDER BY household")]

    def people(self) -> list[str]:
        """Every person the file remembers (in any household), sorted."""
        rows = self._db.execute("SELECT DISTINCT person FROM preferences UNION SELECT person FROM beliefs")
        return sorted(r[0] for r in rows)

    def morning(self, household: str, day: int) -> Snapshot | None:
        """What day ``day`` of ``household`` starts from: the end of the last day before it
        (``None``: no day before it is remembered)."""
        row = self._db.execute(
            "SELECT MAX(day) FROM days WHERE household = ? AND day < ? AND final = 1", (household, day)
        ).fetchone()
        return None if row[0] is None else self._read(household, int(row[0]), True)

    def resume(self, household: str, day: int) -> Snapshot | None:
        """What a brain restarted within day ``day`` resumes from: that day's last checkpoint,
        else the day's morning."""
        row = self._db.execute(
            "SELECT 1 FROM days WHERE household = ? AND day = ? AND final = 0", (household, day)
        ).fetchone()
        return self._read(household, day, False) if row else self.morning(household, day)

    def snapshots(self) -> list[Snapshot]:
        """Everything the file holds, by household, day and kind."""
        rows = self._db.execute("SELECT household, day, final FROM days ORDER BY household, day, final")
        return [self._read(h, d, bool(f)) for h, d, f in rows.fetchall()]

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

    def export(self) -> dict[str, Any]:
        """Everything the file holds as plain JSON-able data (``toyroom memory export``)."""
        return {
            "schema": SCHEMA_VERSION,
            "snapshots": [msgspec.to_builtins(s) for s in self.snapshots()],
        }


def open_memory(path: Path) -> MemoryStore:
    """Open (or create) the memory file at ``path`` and hold it for this process.

    Raises:
        MemoryFileError: not a toyroom memory, damaged, newer, or held by another process.
    """
    path = Path(path)
    if path.is_dir():
        raise MemoryFileError(f"memory file {path} is a folder, not a file")
    try:
        db = sqlite3.connect(path, timeout=LOCK_SECONDS, isolation_level=None)
    except sqlite3.Error as err:
        raise MemoryFileError(f"memory file {path} cannot be opened: {err}") from err
    try:
        db.execute("PRAGMA locking_mode = EXCLUSIVE")
        _claim(db, path)
        _check(db, path)
        _migrate(db, path)
    except BaseException:
        db.close()
        raise
    return MemoryStore(path, db)


def _claim(db: sqlite3.Connection, path: Path) -> None:
    """Take the file's lock (held until close: ``locking_mode = EXCLUSIVE``)."""
    try:
        db.execute("BEGIN IMMEDIATE")
        db.execute("COMMIT")
    except sqlite3.OperationalError as err:
        if "locked" in str(err):
            raise MemoryFileError(
                f"memory file {path} is in use by another process (a running brain, or "
                "toyroom memory): stop it, or give this one another file"
            ) from err
        raise MemoryFileError(f"memory file {path} is not a toyroom memory (damaged?): {err}") from err
    except sqlite3.DatabaseError as err:
        raise MemoryFileError(f"memory file {path} is not a toyroom memory (damaged?): {err}") from err


def _check(db: sqlite3.Connection, path: Path) -> None:
    try:
        (app,) = db.execute("PRAGMA application_id").fetchone()
        (version,) = db.execute("PRAGMA user_version").fetchone()
        tables = {r[0] for r in db.execute("SELECT name FROM sqlite_master WHERE type = 'table'")}
        (check,) = db.execute("PRAGMA quick_check").fetchone()
    except sqlite3.DatabaseError as err:
        raise MemoryFileError(f"memory file {path} is not a toyroom memory (damaged?): {err}") from err
    if check != "ok":
        raise MemoryFileError(f"memory file {path} is damaged: {check}")
    if app != APPLICATION_ID and (tables or version):
        raise MemoryFileError(
            f"memory file {path} is another SQLite file, not a toyroom memory "
            f"(application id {app:#x}, tables {', '.join(sorted(tables)) or 'none'})"
        )
    if version > SCHEMA_VERSION:
        raise MemoryFileError(
            f"memory file {path} was written by a newer toyroom (schema {version}; this one "
            f"reads up to {SCHEMA_VERSION}): upgrade toyroom, or give this brain another file"
        )


def _migrate(db: sqlite3.Connection, path: Path) -> None:
    """Bring the file's schema up to :data:`SCHEMA_VERSION`, one migration per transaction."""
    (version,) = db.execute("PRAGMA user_version").fetchone()
    while version < SCHEMA_VERSION:
        db.execute("BEGIN IMMEDIATE")
        try:
            for statement in MIGRATIONS[version].split(";"):
                if statement.strip():
                    db.execute(statement)
            db.execute(f"PRAGMA application_id = {APPLICATION_ID}")
            db.execute(f"PRAGMA user_version = {version + 1}")
        except sqlite3.Error as err:
            db.execute("ROLLBACK")
            raise MemoryFileError(f"memory file {path}: migrating schema {version} failed: {err}") from err
        db.execute("COMMIT")
        version += 1


def dumps(data: dict[str, Any]) -> str:
    """``export``'s data as indented JSON text."""
    return json.dumps(data, indent=2, sort_keys=True)
