"""Opening a memory file: the checks that refuse it (with a
:class:`~brain.errors.MemoryFileError` naming it) before anything is read or written, its
lock, and its schema brought up to date (:func:`connect`; :func:`brain.memory.store.open_memory`
wraps the connection).

The file is refused when it is not a toyroom memory (another SQLite file, or damaged bytes),
when a newer toyroom wrote it (a schema version above :data:`SCHEMA_VERSION`), when another
process holds it (:class:`~brain.errors.MemoryInUseError`: a brain holds its memory file for
as long as it runs), or, opened for writing, when this process cannot write it. An older
schema is migrated in place.
"""

from __future__ import annotations

import sqlite3
from pathlib import Path

from ..errors import MemoryFileError, MemoryInUseError

APPLICATION_ID = 0x746F7972
"""``PRAGMA application_id`` of a toyroom memory file ("toyr"): another SQLite file has 0."""
SCHEMA_VERSION = 2
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
    1: """
    ALTER TABLE days ADD COLUMN saved_at REAL;
    UPDATE days SET saved_at = CAST(strftime('%s', 'now') AS REAL);
    CREATE TABLE names (
        household TEXT NOT NULL, id TEXT NOT NULL, name TEXT NOT NULL,
        PRIMARY KEY (household, id));
    """,
}
"""SQL that takes a file from schema ``v`` to ``v + 1`` (0: an empty file; 1 -> 2: each day's
clock time, ``saved_at`` in seconds since 1970 UTC (a day saved before it gets the upgrade's time),
and the names the scene gives places and items)."""


def connect(path: Path, *, read_only: bool = False, wait: float = LOCK_SECONDS) -> sqlite3.Connection:
    """Open (or create) the memory file at ``path`` and hold it for this process
    (``read_only``: open an existing file for reading only: nothing is written to it, not
    even a schema).

    Raises:
        MemoryFileError: not a toyroom memory, damaged, newer, held by another process, or
            (not ``read_only``) a file this process cannot write.
    """
    path = Path(path)
    if path.is_dir():
        raise MemoryFileError(f"memory file {path} is a folder, not a file")
    if read_only and not path.is_file():
        raise MemoryFileError(f"no memory file at {path}")
    if read_only and path.stat().st_size == 0:
        raise MemoryFileError(f"memory file {path} is empty (0 bytes): not a toyroom memory")
    try:
        if read_only:
            db = sqlite3.connect(
                f"{path.resolve().as_uri()}?mode=ro", timeout=wait, isolation_level=None, uri=True
            )
        else:
            db = sqlite3.connect(path, timeout=wait, isolation_level=None)
    except sqlite3.Error as err:
        raise MemoryFileError(f"memory file {path} cannot be opened: {err}") from err
    try:
        db.execute("PRAGMA locking_mode = EXCLUSIVE")
        _claim(db, path, read_only)
        _check(db, path)
        if read_only:
            _check_current(db, path)
        else:
            _probe_writable(db, path)
            db.execute("PRAGMA secure_delete = ON")  # deleted rows' bytes are zeroed, not left
            db.execute("PRAGMA journal_size_limit = 0")  # and no journal kept holding old pages
            _migrate(db, path)
    except BaseException:
        db.close()
        raise
    return db


def _claim(db: sqlite3.Connection, path: Path, read_only: bool = False) -> None:
    """Take the file's lock (held until close: ``locking_mode = EXCLUSIVE``; a reader's
    shared lock, read only)."""
    try:
        db.execute("BEGIN" if read_only else "BEGIN IMMEDIATE")
        db.execute("SELECT count(*) FROM sqlite_master").fetchone()
        db.execute("COMMIT")
    except sqlite3.OperationalError as err:
        if "locked" in str(err):
            raise MemoryInUseError(
                f"memory file {path} is in use by another process (a running brain, or "
                "toyroom memory): stop it, or give this one another file"
            ) from err
        if "readonly" in str(err):  # a hot journal a reader may not roll back
            raise MemoryFileError(
                f"memory file {path} was left mid-save (a brain killed while writing): open it "
                "once for writing (a brain with --memory, or toyroom memory forget) to recover it"
            ) from err
        raise MemoryFileError(f"memory file {path} is not a toyroom memory (damaged?): {err}") from err
    except sqlite3.DatabaseError as err:
        raise MemoryFileError(f"memory file {path} is not a toyroom memory (damaged?): {err}") from err


def _probe_writable(db: sqlite3.Connection, path: Path) -> None:
    """Write the file's own schema version back, and roll it back: a file the process may
    not write (read-only, immutable, on a read-only mount) is refused now, not at the first
    save of a running brain."""
    (version,) = db.execute("PRAGMA user_version").fetchone()
    db.execute("BEGIN IMMEDIATE")
    try:
        db.execute(f"PRAGMA user_version = {int(version)}")
    except sqlite3.OperationalError as err:
        raise MemoryFileError(
            f"memory file {path} cannot be written ({err}): the brain saves what it learns "
            "there; make it writable, or give it another file"
        ) from err
    finally:
        db.execute("ROLLBACK")


def _check_current(db: sqlite3.Connection, path: Path) -> None:
    """A file read without writing must already hold this toyroom's schema (no migration)."""
    (version,) = db.execute("PRAGMA user_version").fetchone()
    if version < SCHEMA_VERSION:
        raise MemoryFileError(
            f"memory file {path} holds no toyroom memory yet (schema {version}, an empty "
            f"SQLite file): nothing to read"
        )


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
