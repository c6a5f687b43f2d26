"""Overrides of a generated episode's ``[autonomy]`` table (``python -m sim2d generate
--autonomy NAME=VALUE``, ``toyroom eval --autonomy``): the same episodes with people who
behave otherwise in one respect, for measuring how much a result owes to the simulated
people (``replan_lag = [100000, 100000]``: people who never turn back on their own)."""

from __future__ import annotations

import tomllib
from collections.abc import Mapping, Sequence
from pathlib import Path

from ..errors import ScenarioError
from ..scenario.autonomy import AUTONOMY_KEYS, current_key, parse_autonomy


def parse_override(text: str) -> tuple[str, str]:
    """``NAME=VALUE`` as ``(name, value)``, the value a TOML value (``0.1``, ``[2, 8]``,
    ``"nearest"``). Raises ``ValueError`` naming an unknown key or a value TOML cannot read."""
    name, sep, value = text.partition("=")
    name, value = current_key(name.strip()), value.strip()
    if not sep or not name or not value:
        raise ValueError(f"an autonomy override is NAME=VALUE, not {text!r}")
    if name not in AUTONOMY_KEYS:
        raise ValueError(f"unknown autonomy setting {name!r} (known: {', '.join(sorted(AUTONOMY_KEYS))})")
    try:
        tomllib.loads(f"v = {value}")
    except tomllib.TOMLDecodeError as err:
        raise ValueError(f"autonomy {name}: {value!r} is not a TOML value ({err})") from None
    return name, value


def parse_overrides(texts: Sequence[str]) -> dict[str, str]:
    """Every ``NAME=VALUE`` of ``texts`` (:func:`parse_override`); a later one of a name wins."""
    return dict(parse_override(text) for text in texts)


def with_autonomy(text: str, overrides: Mapping[str, str], path: Path) -> str:
    """The episode TOML ``text`` with each of ``overrides`` set in its ``[autonomy]`` table
    (replacing the generated line of that name, or added to it), checked as a whole.

    Raises:
        ScenarioError: the table the overrides make is not a valid ``[autonomy]`` (a rate
            outside [0, 1], a malformed tick pair...), naming ``path`` and what is wrong.
    """
    if not overrides:
        return text
    lines = text.split("\n")
    start = lines.index("[autonomy]") + 1
    end = next((i for i in range(start, len(lines)) if not lines[i].strip()), len(lines))
    kept = [line for line in lines[start:end] if line.split("=", 1)[0].strip() not in overrides]
    table = [*kept, *(f"{name} = {value}" for name, value in overrides.items())]
    out = "\n".join([*lines[:start], *table, *lines[end:]])
    try:
        data = tomllib.loads(out)
    except tomllib.TOMLDecodeError as err:
        raise ScenarioError(path, "autonomy", f"the overrides do not make TOML ({err})") from None
    parse_autonomy(data, path)
    return out
