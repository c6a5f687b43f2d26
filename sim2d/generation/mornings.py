"""A generated day of a household after the first: the people's lines given what they were
sure of and what they wanted at the end of the day before (:class:`protocol.Morning`)."""

from __future__ import annotations

import tomllib
from collections.abc import Mapping, Sequence


def by_favourites(placed: Mapping[str, str], favourites: Mapping[str, str]) -> dict[str, str]:
    """``placed`` (item -> location) reordered for a task episode, which is built around its
    first item for A1 and gives A2 the second: A1's favourite item first, then A2's when it
    is another, then the rest in their order (unchanged without favourites)."""
    first = [favourites[p] for p in ("A1", "A2") if favourites.get(p) in placed]
    order = list(dict.fromkeys([*first, *placed]))
    return {item: placed[item] for item in order}


def with_beliefs(lines: Sequence[str], beliefs: Mapping[str, Mapping[str, str]]) -> list[str]:
    """``[[agents]]`` lines with each person sure, from the start, of what ``beliefs`` says
    (person -> item -> location): added to a ``believes`` line of their own, for the items
    it and ``knows`` do not name already (a task's own beliefs win)."""
    out: list[str] = []
    for block in _blocks(lines):
        data = tomllib.loads("\n".join(line for line in block if line != "[[agents]]"))
        carried = beliefs.get(str(data.get("id", "")), {})
        named = {item for item, _ in data.get("believes", [])} | set(data.get("knows", []))
        pairs = [*data.get("believes", []), *([i, loc] for i, loc in carried.items() if i not in named)]
        kept = [line for line in block if not line.startswith("believes =")]
        if pairs:
            text = ", ".join(f'["{item}", "{loc}"]' for item, loc in pairs)
            kept.insert(len(kept) - 1 if kept[-1] == "" else len(kept), f"believes = [{text}]")
        out += kept
    return out


def _blocks(lines: Sequence[str]) -> list[list[str]]:
    """``lines`` cut into one block per ``[[agents]]`` table (each from its header on)."""
    blocks: list[list[str]] = []
    for line in lines:
        if line == "[[agents]]" or not blocks:
            blocks.append([])
        blocks[-1].append(line)
    return blocks
