"""Where a robot's help is lost, episode by episode: task episodes (``sim2d generate --kind
tasks``, rich minds) run with ``toyroom run`` and the ``tom`` robot acting, once with an
embodied robot and once with an omniscient one, and per episode the owner's story read off
``events.csv`` and the truth: the first tick the owner held a false belief about the item they
want, the tick the robot began a task about that item (``task`` rows), the tick that task
ended and how, and the tick the owner first played with the item.

    python bench/help_loss.py [--seed 202] [--episodes 12] [--tasks moved,hidden,...]

Columns: ``fb`` the false belief's first tick; ``begin``/``end`` the robot's task on that
item (``-``: none); ``goal`` the owner reached the item; the summary splits the ticks from
``fb`` to ``goal`` into before the robot acted, while it acted, and after.
"""

from __future__ import annotations

import argparse
import csv
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

from bridge.evaluation.generation import generate_all
from bridge.recording.trace import trace_records
from protocol import Truth

FALSE = 0.1
"""A belief giving the item's true place less than this is false (the evaluation's mass)."""


def story(run: Path) -> dict[str, object] | None:
    """The owner's story in one run: the first person to hold a false belief about the item
    they want, and what the robot did about that item."""
    truths = [m for _, _, m in trace_records(run / "trace.jsonl", strict=False) if isinstance(m, Truth)]
    fb: tuple[int, str, str] | None = None
    for truth in truths:
        where = {p.item: p.location for p in truth.items}
        for mind in truth.agents:
            belief = {p.id: p.p for b in mind.beliefs if b.item == mind.preference for p in b.locations}
            if mind.preference in where and belief.get(where[mind.preference], 1.0) < FALSE:
                fb = (truth.tick, mind.agent, mind.preference)
                break
        if fb is not None:
            break
    if fb is None:
        return None
    tick, owner, item = fb
    with (run / "events.csv").open() as handle:
        rows = list(csv.DictReader(handle))
    tasks = [r for r in rows if r["kind"] == "task" and f" {item} " in f" {r['detail']} "]
    begin = next((int(r["tick"]) for r in tasks if r["detail"].startswith("begin")), None)
    ended = next((r for r in tasks if not r["detail"].startswith("begin")), None)
    goal = next(
        (
            int(r["tick"])
            for r in rows
            if r["actor"] == owner and r["kind"] == "play" and r["item"] == item and int(r["tick"]) >= tick
        ),
        None,
    )
    return {
        "fb": tick,
        "owner": owner,
        "item": item,
        "begin": begin,
        "end": int(ended["tick"]) if ended else None,
        "how": ended["detail"].split(":")[0] if ended else "",
        "goal": goal,
    }


def run(scenario: Path, out: Path, perception: str) -> Path:
    command = [sys.executable, "-m", "bridge", "run", "--scenario", str(scenario), "--robot", "act"]
    command += ["--no-live", "--out", str(out), "--set", f"perception={perception}"]
    subprocess.run(command, check=True, capture_output=True)
    return out


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=202)
    parser.add_argument("--episodes", type=int, default=12)
    parser.add_argument("--tasks", default="moved,hidden,contested,seen,told,overlooked,stale")
    parser.add_argument("--out", type=Path, default=None)
    args = parser.parse_args()
    folder = args.out or Path(tempfile.mkdtemp(prefix="help-loss-"))
    print("episode               robot        owner item   fb  begin  end  how            goal")
    split: dict[str, list[tuple[int, int, int]]] = {"embodied": [], "omniscient": []}
    for scenario in generate_all(
        folder / "scenarios", args.episodes, args.seed, "rich", "tasks", 1000, args.tasks.split(",")
    ):
        for perception in split:
            s = story(run(scenario, folder / perception / scenario.stem, perception))
            if s is None:
                continue
            show = {k: "-" if v is None else v for k, v in s.items()}
            print(
                f"{scenario.stem:<21} {perception:<12} {show['owner']:<5} {show['item']:<6} {show['fb']:>4} "
                f"{show['begin']:>5} {show['end']:>4}  {str(show['how']):<14} {show['goal']:>4}"
            )
            goal, fb = s["goal"] or 1000, int(s["fb"])  # type: ignore[arg-type]
            begin = min(s["begin"] or goal, goal)  # type: ignore[type-var]
            end = min(max(s["end"] or begin, begin), goal)  # type: ignore[type-var]
            split[perception].append((max(begin - fb, 0), end - begin, goal - end))
    for perception, parts in split.items():
        if parts:
            before, acting, after = (statistics.mean(p[i] for p in parts) for i in range(3))
            print(
                f"{perception}: {len(parts)} owners; mean ticks from the false belief to the goal: "
                f"{before:.0f} before the robot acted, {acting:.0f} while it acted, {after:.0f} after"
            )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
