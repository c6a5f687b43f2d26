"""A memory file as JSON and back (``toyroom memory export`` and ``import``).

An export holds every day saved (each snapshot with its clock time, ``saved_at``), the names
the scenes give places and items, and the schema it was written under. ``export --person P``
holds only what the file keeps about P (their preferences and beliefs, day by day; no item of
the robot's own knowledge): what a person asks to see of themselves. It says whose it is, and
is not a memory to import.

``import`` writes an export into a new or empty memory file, as it was: exporting the result
gives the same JSON (the round trip is tested).
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Annotated, Any

import msgspec

from ..errors import MemoryFileError
from .opening import SCHEMA_VERSION
from .snapshot import PersonMemory, Snapshot
from .store import MemoryStore, open_memory

Probability = Annotated[float, msgspec.Meta(ge=0.0, le=1.0)]


class Saved(msgspec.Struct, frozen=True, forbid_unknown_fields=True):
    """One snapshot of an export (:class:`~brain.memory.snapshot.Snapshot`'s fields, and the
    clock time it was saved at)."""

    household: str
    day: Annotated[int, msgspec.Meta(ge=1)]
    tick: Annotated[int, msgspec.Meta(ge=0)]
    final: bool
    people: tuple[PersonMemory, ...]
    items: dict[str, dict[str, Probability]]
    saved_at: float | None = None


class Exported(msgspec.Struct, frozen=True, forbid_unknown_fields=True):
    """A memory file as exported: its snapshots, the scenes' names of places and items, whose
    it is (``--person``) and the schema it was written under."""

    schema: int
    snapshots: list[Saved]
    names: dict[str, dict[str, str]] = {}
    person: str | None = None


def export(store: MemoryStore, person: str | None = None, household: str | None = None) -> dict[str, Any]:
    """Everything the file holds as plain JSON-able data; with ``person``, only what it holds
    about them (in ``household``, else in every household that holds them).

    Raises:
        MemoryRequestError: ``person`` (or ``household``) is not in the file.
    """
    saved = store.saved()
    names = store.names()
    data: dict[str, Any] = {"schema": SCHEMA_VERSION}
    if person is not None:
        held = store.people_by_household()
        homes = [store.household_of(person, household)] if household is not None else []
        if not homes:
            homes = [h for h, people in held.items() if person in people] or [
                store.household_of(person, None)
            ]
        saved = [
            (msgspec.structs.replace(s, people=tuple(p for p in s.people if p.person == person), items={}), t)
            for s, t in saved
            if s.household in homes and s.person(person) is not None
        ]
        names = {h: n for h, n in names.items() if h in homes}
        data["person"] = person
    data["snapshots"] = [{**msgspec.to_builtins(s), "saved_at": t} for s, t in saved]
    data["names"] = names
    return data


def dumps(data: dict[str, Any]) -> str:
    """An export as indented JSON text."""
    return json.dumps(data, indent=2, sort_keys=True)


def read_export(path: Path) -> Exported:
    """The export at ``path``, checked.

    Raises:
        MemoryFileError: no such file, not an export, one of one person, or a newer schema's.
    """
    try:
        data = msgspec.json.decode(path.read_bytes(), type=Exported)
    except (FileNotFoundError, IsADirectoryError, NotADirectoryError):
        raise MemoryFileError(f"no export file at {path}") from None
    except OSError as err:
        raise MemoryFileError(f"export {path} cannot be read: {err.strerror or err}") from err
    except (msgspec.DecodeError, msgspec.ValidationError) as err:
        raise MemoryFileError(f"{path} is not an export of toyroom memory export: {err}") from err
    if data.schema > SCHEMA_VERSION:
        raise MemoryFileError(
            f"export {path} was written by a newer toyroom (schema {data.schema}; this one reads "
            f"up to {SCHEMA_VERSION}): upgrade toyroom"
        )
    if data.person is not None:
        raise MemoryFileError(
            f"export {path} holds one person only ({data.person!r}, export --person): not a memory "
            "to import (export the whole file)"
        )
    return data


def import_export(source: Path, memory: Path) -> int:
    """Write the export at ``source`` into the memory file ``memory`` (created if missing);
    how many snapshots.

    Raises:
        MemoryFileError: ``source`` is not an export to import (:func:`read_export`), or
            ``memory`` is not a usable memory file, or already holds days (never merged
            into, never written over).
    """
    data = read_export(source)
    with open_memory(memory) as store:
        held = store.households()
        if held:
            raise MemoryFileError(
                f"memory file {memory} already holds households ({', '.join(held)}): import only "
                "into a new or empty memory file (nothing was written)"
            )
        now = store.clock()
        saved = [
            (
                Snapshot(s.household, s.day, s.tick, s.final, s.people, s.items),
                now if s.saved_at is None else s.saved_at,
            )
            for s in data.snapshots
        ]
        store.restore(saved, data.names)
    return len(saved)
