"""How does the brain read a revealed false belief, stretch by stretch? Belief-task episodes
(``sim2d generate --kind tasks``) are run with ``toyroom run`` (robot observing, default
perception omniscient so that what the robot cannot see is not the question), and for every
revealed stretch (:mod:`toyroom.evaluation.revealed`) this prints the steps the person takes
before reaching the wrong place, the observer's highest P(false belief) for that person and
item before then (detected: above 0.5), its P(the person wants that item) at the stretch's start
and its highest in the stretch, and whether at the start it was sure (> 0.99) the person knew
where the item truly was (a belief formed unseen, which only a lapse row can undo).

A walk to an empty place says that the person believes *something they want* is there, not
which item: with the desire unknown, P(false belief about item k) cannot pass P(wants k), so the
last column bounds what behaviour alone could show in the stretch.

    python studies/read_revealed.py [--seed 5] [--episodes 18] [--set miss=0.2 ...] [--out DIR]

The default seed (5) is not the one the evaluation reports (1): read settings off this, report
them on that.
"""

from __future__ import annotations

import argparse
import csv
import statistics
import subprocess
import sys
import tempfile
from collections import defaultdict
from pathlib import Path

from bridge.recording.trace import trace_records
from protocol import EngineInfo, EpisodeKind, EpisodeSpec, Minds, RobotMode, State, Truth
from toyroom.evaluation.conditions import task_kinds
from toyroom.evaluation.generation import generate_all
from toyroom.evaluation.revealed import stretches

PREFERRED, OTHER = 30.0, 1.0
"""The favourite desire model's utilities (``ModelSettings``): P(wants k) from its expected utility."""


def run(scenario: Path, folder: Path, sets: list[str]) -> Path:
    """``toyroom run`` of one episode, robot observing; its results folder."""
    target = folder / scenario.stem
    command = [
        sys.executable,
        "-m",
        "toyroom",
        "run",
        "--scenario",
        str(scenario),
        "--robot",
        RobotMode.OBSERVE,
        "--no-live",
    ]
    command += ["--out", str(target), *[a for s in sets for a in ("--set", s)]]
    subprocess.run(command, check=True, capture_output=True)
    return target


def read_run(folder: Path) -> tuple[dict, dict, dict, dict[tuple, float]]:
    """Truth by tick, each person's cell by tick, location cells, and mind.csv's online values
    keyed ``(quantity, tick, person, item, value)``."""
    truths, cells, spots = {}, {}, {}
    for _, _key, message in trace_records(folder / "trace.jsonl", strict=False):
        if isinstance(message, EngineInfo):
            spots = {loc.id: (loc.cell.col, loc.cell.row) for loc in message.scene.locations}
        elif isinstance(message, Truth):
            truths[message.tick] = message
        elif isinstance(message, State):
            cells[message.tick] = {a.id: (a.cell.col, a.cell.row) for a in message.agents if a.cell}
    values: dict[tuple, float] = defaultdict(float)
    with (folder / "mind.csv").open() as handle:
        for row in csv.DictReader(handle):
            key = (row["quantity"], int(row["tick"]), row["agent"], row["item"], row["value"])
            values[key] = float(row["p_online"])
    return truths, cells, spots, values


def readings(folder: Path) -> list[dict]:
    """One row per revealed stretch of a run (see the module docstring)."""
    truths, cells, spots, values = read_run(folder)
    rows = []
    for s in stretches(truths, cells, spots):
        ticks = range(s.first, s.deadline)
        true = {p.item: p.location for p in truths[s.first].items}[s.item]

        def wants(tick: int, s=s) -> float:
            utility = values[("desire", tick, s.person, s.item, "utility")]
            return (utility - OTHER) / (PREFERRED - OTHER)

        walked = {cells[t][s.person] for t in ticks if s.person in cells.get(t, {})}
        rows.append(
            {
                "episode": folder.name,
                "person": s.person,
                "item": s.item,
                "steps": len(walked) - 1,
                "sure_knew": values[("belief", s.first, s.person, s.item, true)] > 0.99,
                "p_false_belief": max(values[("false_belief", t, s.person, s.item, "")] for t in ticks),
                "p_wants_start": wants(s.first),
                "p_wants_max": max(wants(t) for t in ticks),
            }
        )
    return rows


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=5, help="the evaluation seed (default 5)")
    parser.add_argument("--episodes", type=int, default=18)
    parser.add_argument("--tasks", default="told,overlooked,stale")
    parser.add_argument("--set", action="append", default=[], help="a brain setting (repeatable)")
    parser.add_argument("--out", type=Path, default=None, help="keep the runs here")
    args = parser.parse_args()
    folder = args.out or Path(tempfile.mkdtemp(prefix="revealed-"))
    scenarios = generate_all(
        folder / "scenarios",
        args.episodes,
        args.seed,
        EpisodeSpec(Minds.RICH, EpisodeKind.TASKS, 1000, task_kinds(args.tasks.split(","))),
    )
    rows = [row for scenario in scenarios for row in readings(run(scenario, folder / "runs", args.set))]
    print("episode              person item   steps sure_knew P(fb)max P(wants)start P(wants)max")
    for r in rows:
        print(
            f"{r['episode']:<20} {r['person']:<6} {r['item']:<6} {r['steps']:>5} {r['sure_knew']!s:>9} "
            f"{r['p_false_belief']:>8.2f} {r['p_wants_start']:>13.2f} {r['p_wants_max']:>11.2f}"
        )
    n = len(rows)
    if not n:
        print("no revealed stretches")
        return 1
    detected = sum(r["p_false_belief"] > 0.5 for r in rows)
    print(
        f"\n{n} stretches, median {statistics.median(r['steps'] for r in rows)} steps; "
        f"detected (P(fb) > 0.5 before the place): {detected} ({detected / n:.2f})"
    )
    print(f"sure at the start that the person knew the true place: {sum(r['sure_knew'] for r in rows)}")
    wanted = sum(r["p_wants_max"] > 0.5 for r in rows)
    print(
        f"P(wants the item) above 0.5 at some tick of the stretch: {wanted} ({wanted / n:.2f}); "
        f"median at the start {statistics.median(r['p_wants_start'] for r in rows):.2f}"
    )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
