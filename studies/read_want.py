"""Where the want is not read (issue 65): each false-belief stretch of an evaluation's
episodes (:mod:`toyroom.evaluation.wantread`: from a person's false belief about the item they
want to their first take of it), split by what the person is doing, with the observer's mean
P(the true want) in each part:

- ``out``: the person is outside (an errand's absence);
- ``in``: inside the house;
- and per stretch: its ticks, the share spent outside, and the mean P(errand) while outside.

The episodes are the ones ``toyroom eval`` generates for the same options; each is run
in-process (sim2d's engine and the brain's tracker, robot observing), so this reads the model
and not the wire. Fit-free: it prints what the model does with the settings given.

    python studies/read_want.py [--episodes 10] [--seed 7] [--set errand_per_s=0 ...]
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
from pathlib import Path

import numpy as np

from brain.settings import ModelSettings, load_settings
from brain.tracking.tracker import MindTracker
from protocol import EpisodeKind, EpisodeSpec, Minds, RobotMode, Truth
from sim2d.engine import Engine
from toyroom.evaluation.generation import generate_all
from toyroom.evaluation.wantread import want_stretches


def run_episode(scenario: Path, settings: ModelSettings) -> list[dict[str, object]]:
    """One row per person-tick of a want stretch: the person, the tick, outside or not,
    P(true want) and P(errand)."""
    engine = Engine(str(scenario), robot=RobotMode.OBSERVE)
    tracker = MindTracker(engine.scene(), settings)
    outside = {c for r in engine.scene().regions if r.kind.value == "outside" for c in r.cells}
    truths: dict[int, Truth] = {}
    rows: dict[tuple[int, str], dict[str, object]] = {}
    takes: list[tuple[int, str, str]] = []
    state, events = engine.state(), ()
    while True:
        tracker.observe(state, events)
        truth = engine.truth()
        if truth is not None:
            truths[state.tick] = truth
        takes += [(e.tick, e.actor, e.item or "") for e in events if e.kind.value == "take"]
        for agent in state.agents:
            est = tracker.online(agent.id) if agent.id in tracker.tracks else None
            if est is None or truth is None:
                continue
            want = next((a.preference for a in truth.agents if a.agent == agent.id), None)
            goals = [*tracker.model.items, "out"]
            p = float(est.preference[goals.index(want)]) if want in goals else 0.0
            errand = float(est.mode[1]) if est.mode is not None else float("nan")
            rows[(state.tick, agent.id)] = {"out": agent.cell in outside, "p": p, "errand": errand}
        if engine.done:
            break
        result = engine.step()
        state, events = result.state, result.events
    wanting = want_stretches(truths, takes)
    return [
        {"tick": tick, "person": person, **rows[(tick, person)]}
        for tick, people in sorted(wanting.items())
        for person in sorted(people)
        if (tick, person) in rows
    ]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--episodes", type=int, default=10)
    parser.add_argument("--seed", type=int, default=7)
    parser.add_argument("--minds", default="rich")
    parser.add_argument("--kind", default="tasks")
    parser.add_argument("--set", action="append", default=[], metavar="NAME=VALUE")
    args = parser.parse_args()
    settings = load_settings(None, ["perception=embodied", *args.set]).model
    with tempfile.TemporaryDirectory() as folder:
        spec = EpisodeSpec(Minds(args.minds), EpisodeKind(args.kind))
        scenarios = generate_all(Path(folder), args.episodes, args.seed, spec)
        everything: list[dict[str, object]] = []
        for scenario in scenarios:
            rows = run_episode(scenario, settings)
            everything += rows
            out = [r for r in rows if r["out"]]
            inside = [r for r in rows if not r["out"]]
            print(
                f"{scenario.stem}: {len(rows)} ticks, {len(out)} outside "
                f"(P {_mean(out, 'p')}, P(errand) {_mean(out, 'errand')}), "
                f"{len(inside)} inside (P {_mean(inside, 'p')})"
            )
    out = [r for r in everything if r["out"]]
    print(
        f"all: {len(everything)} ticks, P(true want) {_mean(everything, 'p')}; outside {len(out)} ticks, "
        f"P {_mean(out, 'p')}; inside P {_mean([r for r in everything if not r['out']], 'p')}"
    )


def _mean(rows: list[dict[str, object]], key: str) -> str:
    values = [float(r[key]) for r in rows if not np.isnan(float(r[key]))]  # type: ignore[arg-type]
    return f"{statistics.fmean(values):.3f}" if values else "-"


if __name__ == "__main__":
    main()
