"""Does ``toyroom fit --refine`` recover ``miss`` and ``hearsay`` from people whose lapses are
known? Episodes on the paper map whose two people act by the brain's own planner (``--minds
model``: :mod:`sim2d.people.planned`) and overlook items (``Autonomy.miss``) and tell each other
where things are (``Autonomy.hearsay_per_tick``) at known rates; then the fit of ``miss`` (and
``hearsay``) over their recordings, grid first, then the optimiser.

What the episodes add to ``--minds model`` ones, so lapses happen often enough to be read:
people start knowing where everything is (``knows = 1``: a sight of a moved item is then a
surprise, the only sight the model's lapse rows split on), and an unseen hand moves a random
resting item to a random free spot every ``--every`` ticks (people rarely move things
themselves). The engine runs in this process (no Zenoh); each episode is written as a
``trace.jsonl`` that ``toyroom fit`` reads.

The simulated rates and the model's are the same quantity for ``miss`` (the chance an item
coming into view at a place goes unnoticed while it stays there), and the same rule for
hearsay (issue 53: a teller surer than the listener tells one item they place differently),
sim2d's ``hearsay_per_tick`` per tick and the model's ``hearsay_per_s`` per second
(``-ln(1 - h) / tick_seconds`` is the matching value, printed as the truth).

    python studies/recover_lapse.py [--miss 0.2] [--hearsay 0.0] [--episodes 40] [--ticks 2000]
        [--workers 2] [--params miss[,hearsay_per_s]] [--json FILE]
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import tempfile
import time
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from brain.outputs.policytable import write_policy_table
from brain.settings import ModelSettings, Settings, current_name
from bridge.recording.trace import Trace, trace_line
from protocol import ClockMode, Keys
from sim2d.engine import Engine
from sim2d.people import load_policy_table
from sim2d.scenario import Scenario, load_scenario
from sim2d.world import World
from toyroom.fitting.fit import fit
from toyroom.fitting.grid import parse_grid
from toyroom.fitting.optimise import parse_bounds, refine

BASE = dataclasses.replace(ModelSettings(), beta=4.0, hazard=0.02, ignorance=1.0)
"""The planner people act by, and the brain's settings the fit starts from."""
GRID = {"miss": "0.01,0.05,0.2,0.5", "hearsay_per_s": "0.01,0.1,1"}


def scenario(miss: float, hearsay: float, ticks: int) -> Scenario:
    """paper-auto with people who act by the planner, start knowing, and lapse at these rates
    (``hearsay`` per tick per pair, sim2d's unit)."""
    base = load_scenario("paper-auto")
    autonomy = dataclasses.replace(
        base.autonomy, planner="model", knows=0.0, miss=miss, hearsay_per_tick=hearsay
    )
    return dataclasses.replace(base, max_ticks=ticks, autonomy=autonomy)


def episode(sc: Scenario, policy: Path, seed: int, every: int) -> Trace:
    """One episode of ``sc`` (``seed``); every ``every`` ticks an unseen hand moves an item
    where a person will see it (:func:`_move`)."""
    engine = Engine(sc, seed=seed, policy=load_policy_table(policy))
    rng = np.random.default_rng([seed, 7])
    ticks = []
    for tick in range(sc.max_ticks):
        if every > 0 and tick % every == every - 1:
            _move(engine, rng)
        result = engine.step()
        ticks.append((result.state, result.events))
    return Trace(engine.info("lapses", ClockMode.LOCKSTEP), tuple(ticks))


def _move(engine: Engine, rng: np.random.Generator) -> None:
    """The unseen hand: for a person (drawn at random) whose wanted item rests out of their
    view, that item to a free spot in their view, so that they either notice it there or, with
    chance ``miss``, overlook it and go on to where they believe it (the sight whose lapse
    behaviour shows); when no person has such an item, a random resting item to a random free
    spot."""
    world = engine.world
    taken = {item.location for item in world.items.values()}
    free = [loc for loc in world.locations.values() if loc.id not in taken]
    people = list(engine.people.values())
    for k in rng.permutation(len(people)):
        person = people[int(k)]
        item = world.items.get(getattr(person, "preference", ""))
        sees = world.map.sees[world.agents[person.id].cell]
        spots = [loc for loc in free if loc.id in sees]
        if item is not None and item.location is not None and item.location not in sees and spots:
            _put(world, item.id, spots[int(rng.integers(len(spots)))].id)
            return
    resting = [item for item in world.items.values() if item.location is not None]
    if resting and free:
        _put(world, resting[int(rng.integers(len(resting)))].id, free[int(rng.integers(len(free)))].id)


def _put(world: World, item: str, spot: str) -> None:
    loc = world.locations[spot]
    world.items[item].location = spot
    world.physics.put_down(item, world.map.centre((loc.cell.col, loc.cell.row)))


def write_trace(path: Path, trace: Trace) -> Path:
    """``trace`` as a ``trace.jsonl`` that :func:`bridge.recording.trace.read_trace` reads back."""
    keys = Keys("lapses")
    with path.open("w", encoding="utf-8") as handle:
        handle.write(trace_line(keys.info, trace.info) + "\n")
        for state, events in trace:
            handle.write(trace_line(keys.state, state) + "\n")
            handle.writelines(trace_line(keys.events, e) + "\n" for e in events)
    return path


def recordings(
    directory: Path,
    miss: float,
    hearsay: float,
    episodes: int,
    ticks: int,
    every: int = 150,
    first_seed: int = 0,
) -> list[Path]:
    """``episodes`` traces (seeds ``first_seed, ...``) written into ``directory``."""
    directory.mkdir(parents=True, exist_ok=True)
    sc = scenario(miss, hearsay, ticks)
    policy = write_policy_table(directory / "policy.npz", Engine(sc, check_policy=False).scene(), BASE)
    return [
        write_trace(directory / f"lapses-s{seed}.jsonl", episode(sc, policy, seed, every))
        for seed in range(first_seed, first_seed + episodes)
    ]


def recover(traces: Sequence[Path], params: Sequence[str], workers: int) -> dict[str, object]:
    """The grid fit (graded model, 2 folds) and the optimiser's refinement of ``params``."""
    began = time.perf_counter()
    grid = parse_grid(",".join(params), [f"{p}={GRID[p]}" for p in params])
    fits = fit(traces, grid, ["graded"], Settings(model=BASE), 2, 0, workers, False)
    grid_seconds = time.perf_counter() - began
    refined = refine(traces, "graded", fits[0].fitted, BASE, parse_bounds(list(params)), workers=workers)
    return {"grid": fits[0].fitted, "grid_seconds": round(grid_seconds, 1), "refined": refined.as_json()}


def main(argv: Sequence[str] | None = None) -> dict[str, object]:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--miss", type=float, default=0.2, help="sim2d's miss (per item sight)")
    parser.add_argument("--hearsay", type=float, default=0.0, help="sim2d's hearsay (per tick per pair)")
    parser.add_argument("--episodes", type=int, default=40)
    parser.add_argument("--ticks", type=int, default=2000)
    parser.add_argument("--every", type=int, default=150, help="ticks between the unseen hand's moves")
    parser.add_argument("--seed", type=int, default=0, help="the first episode's seed")
    parser.add_argument("--params", default="miss", help="comma-separated: miss, hearsay_per_s or both")
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--json", type=Path, help="also write the numbers here")
    args = parser.parse_args(argv)
    params = [current_name(p.strip()) for p in args.params.split(",") if p.strip()]
    with tempfile.TemporaryDirectory() as scratch:
        began = time.perf_counter()
        traces = recordings(
            Path(scratch), args.miss, args.hearsay, args.episodes, args.ticks, args.every, args.seed
        )
        generated = time.perf_counter() - began
        result = recover(traces, params, args.workers)
    truth = {"miss": args.miss, "hearsay_per_s": -math.log1p(-args.hearsay) / 0.1}
    result |= {"truth": {p: truth[p] for p in params}, "generate_seconds": round(generated, 1)}
    refined = result["refined"]
    assert isinstance(refined, dict)
    print(f"{args.episodes} episodes of {args.ticks} ticks generated in {generated:.1f} s")
    for p in params:
        got = refined["point"][p]
        print(
            f"{p}: true {truth[p]:.4g}, grid {result['grid'][p]:.4g} ({result['grid_seconds']} s), "  # type: ignore[index]
            f"optimiser {got:.4g} (ratio {got / truth[p]:.2f}; {refined['evaluations']} evaluations, "
            f"{refined['seconds']} s, converged: {refined['converged']})"
        )
    if args.json:
        args.json.write_text(json.dumps(result, indent=2), encoding="utf-8")
    return result


if __name__ == "__main__":
    main()
