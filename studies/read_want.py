"""Where the want is not read (issue 65): each false-belief stretch of an evaluation's
episodes (:mod:`toyroom.evaluation.wantread`: from a person's false belief about the item they
want to their first take of it), split by what the person is doing, with the observer's mean
P(the true want) in each part:

- ``out``: the person is outside (an errand's absence);
- ``in``: inside the house;
- and per stretch: its ticks, the share spent outside, and the mean P(errand) while outside.

Beside the observer's reading, ``given``: the same model's P(the true want) when each person's
true belief is handed to it at every decision (from the engine's truth), so that only the
desire is inferred, from the very decisions the observer read (its likeliest branch's). It
bounds what reading beliefs better could give: where ``given`` stays low, the decisions
themselves do not show the want (an errand, a wait, a walk that serves several goals); where
it is high and the observer is low, the belief is what is misread.

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

from brain.model.graded import qmdp_likelihood
from brain.model.inference import switched
from brain.model.person.gradedperson import GradedModel
from brain.settings import ModelSettings, load_settings
from brain.tracking.tracker import MindTracker
from protocol import EpisodeKind, EpisodeSpec, Minds, RobotMode, Truth
from protocol.itemvalue import value_of
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
    given = {p: given_belief_wants(tracker, truths, p) for p in tracker.people}
    return [
        {
            "tick": tick,
            "person": person,
            **rows[(tick, person)],
            "given": _at(given[person], tick, truths, person, tracker.model.items),
        }
        for tick, people in sorted(wanting.items())
        for person in sorted(people)
        if (tick, person) in rows
    ]


def true_belief(model: GradedModel, truth: Truth, person: str, values: tuple[int, ...]) -> np.ndarray:
    """``(W,)`` ``person``'s true belief over the model's worlds: each item resting where their
    belief puts it (independently per item, as sim2d's people hold them); a carried item at its
    true value (``values``) when they hold it or believe it where its carrier is (sim2d's
    people place a carried item at its carrier's location)."""
    world = model.model
    locations = list(world.locations)
    mind = next(a for a in truth.agents if a.agent == person)
    carried = {p.item: p for p in truth.items if p.held_by is not None}
    per_item = []
    for k, item in enumerate(world.items):
        column = np.zeros(world.n_values)
        belief = next((b for b in mind.beliefs if b.item == item), None)
        for entry in () if belief is None else belief.locations:
            if entry.id in locations:
                column[value_of(locations.index(entry.id))] += entry.p
        if column.sum() <= 0:
            column[[value_of(i) for i in range(len(locations))]] = 1.0  # no idea: anywhere
        column /= column.sum()
        place = carried.get(item)
        if place is not None and (
            place.held_by == person or column[value_of(locations.index(place.location))] >= 0.5
        ):
            column[:] = 0.0  # they hold it, or know who carries it (sim2d's belief: the carrier's place)
            column[values[k]] = 1.0
        per_item.append(column)
    joint = per_item[0]
    for column in per_item[1:]:
        joint = np.multiply.outer(joint, column).reshape(-1)
    return joint


def given_belief_wants(tracker: MindTracker, truths: dict[int, Truth], person: str) -> dict[int, np.ndarray]:
    """Tick of each decision -> ``(D,)`` P(each goal is the most wanted), the model's desire
    filter run on ``person``'s decisions (the likeliest branch's steps) with their true belief
    (at the tick before each decision) instead of the model's hypotheses."""
    model = tracker.person_model
    if not isinstance(model, GradedModel) or model.lookahead is not None:
        raise SystemExit("given beliefs need the graded model with the qmdp planner (the default)")
    s = tracker.settings
    U = len(model.policy.utilities)
    posterior = np.full((1, U), 1.0 / U)
    out: dict[int, np.ndarray] = {}
    for record in tracker.tracks[person].steps:
        before = max((t for t in truths if t < record.tick), default=None)
        if record.decision is not None and before is not None and before in tracker.truths:
            cell, held, action = record.decision
            belief = true_belief(model, truths[before], person, tracker.truths[before])
            q = model.policy.q[:, model.policy.state_slice(cell, held), :]
            posterior = switched(posterior, record.switch) * qmdp_likelihood(
                belief[None, :], q, action, s.beta, s.epsilon
            )
            posterior = posterior / posterior.sum()
        out[record.tick] = posterior[0] @ model.desires.wanted
    return out


def _at(
    wants: dict[int, np.ndarray], tick: int, truths: dict[int, Truth], person: str, items: tuple[str, ...]
) -> float:
    """P(``person``'s true want at ``tick``) from their latest given-belief reading by then
    (the uniform prior before their first step)."""
    mind = next(a for a in truths[tick].agents if a.agent == person)
    steps = [t for t in wants if t <= tick]
    if not steps:
        return float("nan")
    reading = wants[max(steps)]
    goal = items.index(mind.preference) if mind.preference in items else len(items)  # ``out`` last
    return float(reading[goal])


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
                f"{len(inside)} inside (P {_mean(inside, 'p')}); given beliefs P {_mean(rows, 'given')}"
            )
    out = [r for r in everything if r["out"]]
    print(
        f"all: {len(everything)} ticks, P(true want) {_mean(everything, 'p')}; outside {len(out)} ticks, "
        f"P {_mean(out, 'p')}; inside P {_mean([r for r in everything if not r['out']], 'p')}"
    )
    inside = [r for r in everything if not r["out"]]
    print(
        f"given each person's true belief: P(true want) {_mean(everything, 'given')}; outside "
        f"{_mean(out, 'given')}; inside {_mean(inside, 'given')}; share >= 0.6: "
        f"{_share(everything, 'given')} (observer: {_share(everything, 'p')})"
    )


def _share(rows: list[dict[str, object]], key: str, threshold: float = 0.6) -> str:
    values = [float(r[key]) for r in rows if not np.isnan(float(r[key]))]  # type: ignore[arg-type]
    return f"{statistics.fmean(v >= threshold for v in values):.3f}" if values else "-"


def _mean(rows: list[dict[str, object]], key: str) -> str:
    values = [float(r[key]) for r in rows if not np.isnan(float(r[key]))]  # type: ignore[arg-type]
    return f"{statistics.fmean(values):.3f}" if values else "-"


if __name__ == "__main__":
    main()
