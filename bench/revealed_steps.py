"""Do the belief tasks give behaviour a chance to speak? For each revealed stretch of a folder of
generated episodes (the scenarios an evaluation wrote), replayed in sim2d in-process: whether the
person takes a step away from where the item is before reaching the wrong place (a step nobody
heading for the item would take), and how many ticks are left after it.

    python bench/revealed_steps.py OUT/eval/toyroom-eval-*/CONDITION/scenarios
"""

from __future__ import annotations

import argparse
import statistics
from pathlib import Path

from protocol.carry import walking_distances
from sim2d.engine import Engine
from sim2d.scenario import load_scenario
from toyroom.evaluation.revealed import stretches


def stretch_steps(path: Path, max_ticks: int = 1000) -> list[int | None]:
    """Per stretch of the episode at ``path``: ticks left after its first step away from the
    item, before the deadline (``None``: no such step)."""
    engine = Engine(load_scenario(str(path)), seed=0)
    truth = engine.truth()
    assert truth is not None, f"{path}: no autonomous people"
    truths, cells = {0: truth}, {}
    while not engine.done and engine.world.tick < max_ticks:
        result = engine.step()
        assert result.truth is not None
        truths[result.truth.tick] = result.truth
        cells[result.truth.tick] = {a: engine.world.agents[a].cell for a in engine.world.agents}
    spots = {loc.id: (loc.cell.col, loc.cell.row) for loc in engine.world.map.locations}
    out: list[int | None] = []
    for stretch in stretches(truths, cells, spots):
        where = {p.item: p.location for p in truths[stretch.first].items}[stretch.item]
        far = walking_distances(engine.world.map.walkable, [spots[where]])
        left, before = None, cells.get(stretch.first, {}).get(stretch.person)
        for tick in range(stretch.first + 1, stretch.deadline):
            cell = cells.get(tick, {}).get(stretch.person)
            if cell is not None and before is not None and far.get(cell, 0) > far.get(before, 0):
                left = stretch.deadline - tick
                break
            before = cell
        out.append(left)
    return out


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("folder", type=Path, help="a folder of generated episodes (gen-*.toml)")
    args = parser.parse_args()
    lefts = [
        left
        for path in sorted(args.folder.glob("gen-*-s*.toml"))
        if not path.name.endswith(".map.toml")
        for left in stretch_steps(path)
    ]
    shown = [left for left in lefts if left is not None]
    median = statistics.median(shown) if shown else None
    print(
        f"{len(lefts)} stretches; {len(shown)} ({len(shown) / max(len(lefts), 1):.0%}) with a step away "
        f"from the item before the deadline; median ticks left after it: {median}"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
