"""A generated day of a household after the first: the people's lines given what they were
sure of and what they wanted at the end of the day before (:class:`protocol.Morning`)."""

from __future__ import annotations

import tomllib
from collections.abc import Iterable, Mapping, Sequence

from protocol import Morning


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


class MorningError(ValueError):
    """A morning (``--morning FILE``) that does not fit the household it would start a day of:
    another household's or map's, or naming an item, place, person or goal the household does
    not have, or leaving out an item or a person. One line naming what is wrong."""


def _names(ids: Iterable[str]) -> str:
    return ", ".join(repr(i) for i in sorted(ids))


def check_morning(
    morning: Morning,
    household: str,
    map_name: str,
    first_day: str,
    spots: Sequence[str],
    goals: Sequence[str],
) -> None:
    """Check ``morning`` strictly against the household ``household`` on ``map_name``, whose
    first day is the episode TOML ``first_day``: its items, people, places (``spots``) and
    goals (``goals``, with ``out``).

    Raises:
        MorningError: the first thing wrong, in one line.
    """
    if morning.household is None or morning.map is None:
        raise MorningError(
            "names no household and map (a morning written before they were required): add "
            f'"household": "{household}", "map": "{map_name}" if it is this household\'s end of day'
        )
    if (morning.household, morning.map) != (household, map_name):
        raise MorningError(
            f"is the end of a day of household {morning.household!r} on map {morning.map!r}, not of "
            f"household {household!r} on map {map_name!r}"
        )
    data = tomllib.loads(first_day)
    items = [str(item["id"]) for item in data.get("items", [])]
    people = [str(a["id"]) for a in data.get("agents", []) if a.get("kind", "person") == "person"]
    where = f"the household's items are {_names(items)}"
    if unknown := set(morning.items) - set(items):
        raise MorningError(f"names unknown items {_names(unknown)} ({where})")
    if missing := set(items) - set(morning.items):
        raise MorningError(f"names no place for items {_names(missing)} ({where})")
    for item, place in sorted(morning.items.items()):
        if place not in spots:
            raise MorningError(
                f"puts item {item!r} at {place!r}, not a place of map {map_name!r} ({_names(spots)})"
            )
    who = f"the household's people are {_names(people)}"
    if unknown := (set(morning.beliefs) | set(morning.favourites)) - set(people):
        raise MorningError(f"names unknown people {_names(unknown)} ({who})")
    if missing := set(people) - set(morning.favourites):
        raise MorningError(f"names no favourite for {_names(missing)} ({who})")
    for person, beliefs in sorted(morning.beliefs.items()):
        for item, place in sorted(beliefs.items()):
            if item not in items:
                raise MorningError(f"{person!r} believes in unknown item {item!r} ({where})")
            if place not in spots:
                raise MorningError(
                    f"{person!r} believes item {item!r} is at {place!r}, not a place of map {map_name!r}"
                )
    wanted = list(dict.fromkeys([*goals, "out"]))
    for person, goal in sorted(morning.favourites.items()):
        if goal not in wanted:
            raise MorningError(
                f"{person!r}'s favourite {goal!r} is not a goal of the household ({_names(wanted)})"
            )
