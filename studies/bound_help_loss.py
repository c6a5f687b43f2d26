"""Where a robot's help is lost, person by person: task episodes (``sim2d generate --kind
tasks``, rich minds) run with ``toyroom run``, once with the robot observing (``none``) and
once per robot setting acting, and for every person who came to hold a false belief about the
item they wanted, read off the truth and ``events.csv``:

- ``fb``: the first tick of that false belief; ``goal``: the first tick from then on they
  played with the item (the episode's length when never), per run;
- ``told``: when they would have had it, told where it is at ``fb`` (their walk from where
  they stood then, at the engine's walking pace; ``goal`` when someone else held it then):
  what no word can beat (an optimistic bound: a scripted person may not act on the word at
  once, an errand first);
- ``robot``: the same, told by a robot that knew everything at ``fb`` and walked into earshot
  (:data:`protocol.EARSHOT_CELLS`) from where it stood (what an omniscient, instant decider could do);
- ``begin``: the tick the acting robot began a task about the item (``-``: none).

    python studies/bound_help_loss.py [--seed 303] [--episodes 14] [--tasks moved,...] [--perception embodied]

The summary splits the mean ticks to the goal (counted from tick 0, as the evaluation's
``ticks_to_goal_fb``) of ``none`` into: before the false belief, the walk no telling saves
(``told``), the robot's walk into earshot (``robot`` less ``told``), and what is left to save;
and gives each acting setting's mean, for the loss table of ``docs/evaluation.md``.
"""

from __future__ import annotations

import argparse
import csv
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

from brain.model.world import build_world_model
from brain.robot.benefit import cell_distances
from bridge.recording.trace import trace_records
from protocol import (
    EARSHOT_CELLS,
    EngineInfo,
    EpisodeKind,
    EpisodeSpec,
    Minds,
    RobotMode,
    State,
    Truth,
    believes_falsely,
)
from toyroom.evaluation.conditions import task_kinds
from toyroom.evaluation.generation import generate_all


def owners(run: Path) -> list[dict[str, object]]:
    """Every person of a run who held a false belief about the item they wanted (the one rule,
    :func:`protocol.believes_falsely`, as the evaluation's ``ticks_to_goal_fb``): its first
    tick, their goal tick, and the bounds ``told`` and ``robot`` (see the module's text)."""
    records = [m for _, _, m in trace_records(run / "trace.jsonl", strict=False)]
    info = next(m for m in records if isinstance(m, EngineInfo))
    truths = {m.tick: m for m in records if isinstance(m, Truth)}
    states = {m.tick: m for m in records if isinstance(m, State)}
    model = build_world_model(info.scene)
    steps = cell_distances(model)
    with (run / "events.csv").open() as handle:
        rows = list(csv.DictReader(handle))
    last = max(truths)
    found: dict[str, dict[str, object]] = {}
    for tick in sorted(truths):
        truth, state = truths[tick], states.get(tick)
        where = {p.item: p.location for p in truth.items}
        for mind in truth.agents:
            if mind.agent in found or state is None:
                continue
            belief = {p.id: p.p for b in mind.beliefs if b.item == mind.preference for p in b.locations}
            place = where.get(mind.preference)
            if place is None or place not in model.locations or not believes_falsely(belief, place):
                continue
            cells = {a.id: model.cell_index.get((a.cell.col, a.cell.row)) for a in state.agents}
            robot = next((a.id for a in info.scene.agents if a.kind.value == "robot"), None)
            spot = int(np.argmin(model.distance[model.locations.index(place)]))
            walk = float(steps[cells[mind.agent], spot])
            reach = max(float(steps[cells[robot], cells[mind.agent]]) - EARSHOT_CELLS, 0.0) if robot else 0.0
            pace = info.tick_seconds and round(0.7 / info.tick_seconds)  # a cell per decision time
            goal = next(
                (
                    int(r["tick"])
                    for r in rows
                    if r["actor"] == mind.agent
                    and r["kind"] == "play"
                    and r["item"] == mind.preference
                    and int(r["tick"]) >= tick
                ),
                last,
            )
            begin = next(
                (
                    int(r["tick"])
                    for r in rows
                    if r["kind"] == "task"
                    and r["detail"].startswith("begin")
                    and f" {mind.preference} " in r["detail"]
                ),
                None,
            )
            held = next((p.held_by for p in truth.items if p.item == mind.preference), None)
            if held not in (None, mind.agent):  # someone else has it: no word gets it to them
                walk = reach = float(goal - tick) / max(pace, 1)
            found[mind.agent] = {
                "person": mind.agent,
                "item": mind.preference,
                "fb": tick,
                "goal": goal,
                "told": min(tick + pace * walk, goal),
                "robot": min(tick + pace * (reach + walk), goal),
                "begin": begin,
            }
    return list(found.values())


def run(scenario: Path, out: Path, robot: str, extra: list[str]) -> Path:
    command = [sys.executable, "-m", "toyroom", "run", "--scenario", str(scenario), "--robot", robot]
    command += ["--no-live", "--out", str(out), *extra]
    subprocess.run(command, check=True, capture_output=True)
    return out


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=303)
    parser.add_argument("--episodes", type=int, default=14)
    parser.add_argument("--tasks", default="moved,hidden,contested,seen,told,overlooked,stale")
    parser.add_argument("--perception", default="embodied")
    parser.add_argument(
        "--policies",
        default="tom,benefit",
        help="acting policies, comma-separated (none: only the observing runs and the bounds)",
    )
    parser.add_argument("--out", type=Path, default=None)
    args = parser.parse_args()
    folder = args.out or Path(tempfile.mkdtemp(prefix="help-loss-"))
    policies = [p for p in args.policies.split(",") if p not in ("", "none")]  # none: bounds only
    see = ["--set", f"perception={args.perception}"]
    print(f"{'episode':<21} {'who':<4} {'item':<6} {'fb':>4} {'told':>5} {'robot':>5} {'none':>5} ", end="")
    print(" ".join(f"{p:>6} {'begin':>5}" for p in policies))
    totals: dict[str, list[float]] = {k: [] for k in ["fb", "told", "robot", "none", *policies]}
    for scenario in generate_all(
        folder / "scenarios",
        args.episodes,
        args.seed,
        EpisodeSpec(Minds.RICH, EpisodeKind.TASKS, 1000, task_kinds(args.tasks.split(","))),
    ):
        observed = run(scenario, folder / "none" / scenario.stem, RobotMode.OBSERVE, see)
        base = {o["person"]: o for o in owners(observed)}
        acting = {
            p: {
                o["person"]: o
                for o in owners(
                    run(scenario, folder / p / scenario.stem, RobotMode.ACT, [*see, "--set", f"policy={p}"])
                )
            }
            for p in policies
        }
        for person, o in base.items():
            cols = [acting[p].get(person, {}) for p in policies]
            shown = " ".join(f"{c.get('goal', '-'):>6} {c.get('begin') or '-':>5}" for c in cols)
            print(
                f"{scenario.stem:<21} {person:<4} {o['item']:<6} {o['fb']:>4} {o['told']:>5.0f} "
                f"{o['robot']:>5.0f} {o['goal']:>5} {shown}"
            )
            for key in ("fb", "told", "robot"):
                totals[key].append(float(o[key]))  # type: ignore[arg-type]
            totals["none"].append(float(o["goal"]))  # type: ignore[arg-type]
            for p, c in zip(policies, cols, strict=True):
                totals[p].append(float(c.get("goal", o["goal"])))  # type: ignore[arg-type]
    n = len(totals["none"])
    if not n:
        print("no person held a false belief")
        return 0
    mean = {k: statistics.mean(v) for k, v in totals.items()}
    print(f"\n{n} people with a false belief; mean ticks from tick 0 to the goal (ticks_to_goal_fb):")
    print(f"  none {mean['none']:.0f}: {mean['fb']:.0f} before the false belief, ", end="")
    print(f"{mean['told'] - mean['fb']:.0f} walking no telling saves, ", end="")
    print(f"{mean['robot'] - mean['told']:.0f} the robot's walk into earshot, ", end="")
    print(f"{mean['none'] - mean['robot']:.0f} left to save")
    for key in ("told", "robot", *policies):
        cut = 1 - mean[key] / mean["none"]
        print(f"  {key:<6} {mean[key]:.0f} ({cut:+.0%} against none)")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
