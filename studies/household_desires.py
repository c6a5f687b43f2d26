"""Does the memory give the brain each person's desire? Read off a ``toyroom eval --days N``
output folder (its ``work/`` kept): for every person with a false belief on a day, the brain's
P(they want most the item they truly want) at the day's first tick and at the first tick of
their false belief, observing with its memory (``btom``) and without (``btom-fresh``), by day.

    python studies/household_desires.py OUT

Numbers for people, not a test. The truth is each day's scenario (``prefers``) and the day's
record in ``episodes.json`` (``help``: who had a false belief, from which tick).
"""

from __future__ import annotations

import argparse
import gzip
import json
import statistics
import tomllib
from pathlib import Path


def wanted(minds: Path, tick: int, person: str, item: str) -> float | None:
    """P(``person`` wants ``item`` most) in the first mind at or after ``tick`` of a minds file
    (or its ``.gz``, as a finished evaluation keeps it)."""
    packed = minds.with_name(f"{minds.name}.gz")
    text = minds.read_text() if minds.exists() else gzip.decompress(packed.read_bytes()).decode()
    for line in text.splitlines():
        mind = json.loads(line)
        if mind["tick"] < tick:
            continue
        for agent in mind["agents"]:
            if agent["agent"] == person:
                return next((p["p"] for p in agent["preference"] if p["id"] == item), 0.0)
    return None


def rows(out: Path) -> list[tuple[int, str, float, float, float, float]]:
    """(day, person, with memory at tick 0, without, with memory at the false belief, without)."""
    found = []
    for condition, records in json.loads((out / "episodes.json").read_text()).items():
        for record in records:
            if record.get("error"):
                continue
            home = out / "work" / condition / f"household-{record['index']}"
            scenario = home / "scenarios" / "observe" / f"{record['scenario']}.toml"
            prefers = {a["id"]: a.get("prefers") for a in tomllib.loads(scenario.read_text())["agents"]}
            tag = f"{record['scenario']}-btom-observe.shadows/minds-btom.jsonl"
            remembering, fresh = home / "logs" / "observe" / tag, home / "logs" / "observe-fresh" / tag
            for person, helped in record["btom"]["help"].items():
                item, onset = prefers.get(person), helped["false_belief_tick"]
                if not helped["false_belief"] or item is None or onset is None:
                    continue
                values = [
                    wanted(path, tick, person, item) for tick in (0, onset) for path in (remembering, fresh)
                ]
                if None not in values:
                    found.append((record["day"], person, *values))  # type: ignore[arg-type]
    return found


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("out", type=Path, help="a toyroom eval --days output folder")
    found = rows(parser.parse_args().out)
    print("| day | people | P(wanted) at tick 0: memory / none | at the false belief: memory / none |")
    print("| --- | --- | --- | --- |")
    for day in sorted({r[0] for r in found}):
        some = [r for r in found if r[0] == day]
        means = [statistics.fmean(r[i] for r in some) for i in range(2, 6)]
        print(f"| {day} | {len(some)} | {means[0]:.2f} / {means[1]:.2f} | {means[2]:.2f} / {means[3]:.2f} |")


if __name__ == "__main__":
    main()
