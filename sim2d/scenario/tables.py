"""Strict tables: every table of a scenario or map file may hold only the keys its reader
knows. A misspelt key (``max_tiks``, ``speeed``, ``colour``, ``wals``) would otherwise be
ignored without a word, so it is an error naming the key, the closest known key and the
known keys, as script steps (:mod:`sim2d.scenario.script`) have always been.

The known keys of each table kind are here, in one place: the file format's vocabulary; and
so is what a table's ``id`` may be (:func:`table_id`): a protocol id, refused while reading,
not at the handshake after the nodes have started.
"""

from __future__ import annotations

import difflib
from collections.abc import Collection
from pathlib import Path
from typing import Any

from protocol.message import id_problem

from ..errors import ScenarioError

SCENARIO_KEYS = frozenset(
    {
        "name",
        "map",
        "description",
        "robot",
        "observed",
        "tick_seconds",
        "max_ticks",
        "settle_ticks",
        "items",
        "agents",
        "autonomy",
        "household",
        "study",
    }
)
"""A scenario file's top level."""

JOB_TABLE_KEYS = frozenset(
    {
        "errand",
        "errand_after",
        "move",
        "move_after",
        "wait",
        "tell",
        "tell_after",
        "knows",
        "believes",
        "overlooks",
    }
)
"""An autonomous person's first jobs in a task episode (:mod:`sim2d.scenario.jobs`)."""

AGENT_KEYS = frozenset(
    {"id", "kind", "name", "home", "wants", "answers", "script", "autonomous", "prefers"} | JOB_TABLE_KEYS
)
"""A scenario's ``[[agents]]`` table."""

ITEM_KEYS = frozenset({"id", "shape", "at", "name", "absent"})
"""A scenario's ``[[items]]`` table."""

MAP_KEYS = frozenset(
    {"name", "cell_size", "columns", "rows", "regions", "doors", "locations", "visibility", "homes"}
)
"""A map file's top level (``homes`` is a table of agent ids, any ids)."""

REGION_KEYS = frozenset({"id", "kind", "name", "rects"})
DOOR_KEYS = frozenset({"id", "cell", "joins"})
LOCATION_KEYS = frozenset({"id", "region", "cell", "play", "use", "capacity"})
VISIBILITY_KEYS = frozenset({"from", "sees"})


def check_keys(table: Any, known: Collection[str], path: Path, entry: str) -> dict[str, Any]:
    """``table``, once it is a table holding only ``known`` keys.

    Raises:
        ScenarioError: ``table`` is no table, or holds a key not in ``known``: the message
            names each unknown key with the closest known one (by :mod:`difflib`; a key close
            to none, such as ``colour``, is said to be so), and every known key.
    """
    if not isinstance(table, dict):
        raise ScenarioError(path, entry, f"expected a table of keys and values, got {table!r}")
    unknown = [key for key in table if key not in known]
    if not unknown:
        return table
    named = []
    for key in unknown:
        closest = difflib.get_close_matches(key, sorted(known), n=1)
        named.append(
            f"'{key}' " + (f"(did you mean '{closest[0]}'?)" if closest else "(none of the known is close)")
        )
    listed = ", ".join(sorted(known))
    problem = f"unknown key{'s' if len(unknown) > 1 else ''} {', '.join(named)}; known keys: {listed}"
    raise ScenarioError(path, entry, problem)


def entry_of(table: Any, section: str, i: int) -> str:
    """How errors name ``section[i]``: with its id when it has one (``agents[1] 'anne'``)."""
    name = table.get("id") if isinstance(table, dict) else None
    return f"{section}[{i}] '{name}'" if isinstance(name, str) and name else f"{section}[{i}]"


def tables(data: dict[str, Any], key: str, path: Path, limit: int | None = None) -> list[Any]:
    """``data[key]``, an array of tables (``[[key]]``; empty when absent) of at most ``limit``
    (:mod:`protocol.limits`). Each element is checked by its reader, with :func:`check_keys`.

    Raises:
        ScenarioError: ``data[key]`` is not an array (a single ``[key]`` table, a string...),
            or holds more than ``limit`` tables.
    """
    value = data.get(key, [])
    if not isinstance(value, list):
        raise ScenarioError(path, key, f"expected an array of tables ([[{key}]]), got {value!r}")
    if limit is not None and len(value) > limit:
        raise ScenarioError(path, key, f"{len(value):,} {key}, above the limit of {limit:,}")
    return value


def table_id(table: dict[str, Any], path: Path, entry: str) -> str:
    """The ``id`` of the table ``entry``: a protocol id (:func:`protocol.message.id_problem`:
    no space, ``*`` or emoji, which no message may carry).

    Raises:
        ScenarioError: it is missing, not a string, or no id.
    """
    value = table.get("id")
    if not isinstance(value, str) or not value:
        raise ScenarioError(path, entry, f"expected a non-empty string 'id', got {value!r}")
    if (problem := id_problem(value)) is not None:
        raise ScenarioError(path, entry, f"id {problem}")
    return value
