"""People who act by the brain's planner (sim2d's ``planner = "model"``) stand for a Stay
exactly as long as the tracker reads one Stay: every Stay they make is read as one, however
many come in a row and whatever comes before and after (a move, a take, a drop, a play)."""

from __future__ import annotations

import dataclasses
from pathlib import Path

from brain.outputs.policytable import action_names, write_policy_table
from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from sim2d.engine import Engine
from sim2d.people import PlannedPerson, load_policy_table
from sim2d.scenario import load_scenario

SETTINGS = dataclasses.replace(ModelSettings(), beta=0.3, hazard=0.02, belief_model="point")
"""Far from rational: many Stays, many in a row."""


def expected_reading(
    person: PlannedPerson, tracker: MindTracker, cells: dict[int, int], first: int
) -> list[str]:
    """What the tracker should read of ``person``'s decisions: each as made, except Stays it
    reads no wait in (on an outside cell, after playing until the next other action, before
    the first decision it sees at tick ``first``). ``cells``: tick -> cell index."""
    out, settled = [], False
    for tick, name, _ in person.decisions:
        outside = bool(tracker.model.outside[cells[tick]])
        if name != "stay":
            settled = name == "play" or outside
            out.append(name)
        elif not (settled or outside or tick < first):
            out.append(name)
    return out


def test_every_stay_a_planned_person_makes_is_read_as_one(tmp_path: Path) -> None:
    scenario = load_scenario("paper-auto")
    scenario = dataclasses.replace(scenario, autonomy=dataclasses.replace(scenario.autonomy, planner="model"))
    scene = Engine(scenario, check_policy=False).scene()
    table = load_policy_table(write_policy_table(tmp_path / "policy.npz", scene, SETTINGS))
    in_a_row = 0
    for seed in (0, 1):
        engine = Engine(scenario, seed=seed, policy=table)
        tracker = MindTracker(scene, SETTINGS)
        cells: dict[str, dict[int, int]] = {p: {} for p in engine.people}
        for _ in range(1500):
            result = engine.step()
            tracker.observe(result.state, result.events)
            for a in result.state.agents:
                if a.id in cells:
                    cells[a.id][result.state.tick] = tracker.model.cell_index[(a.cell.col, a.cell.row)]
        names = action_names(tracker.model.items)
        for agent, person in engine.people.items():
            assert isinstance(person, PlannedPerson)
            steps = [s for s in tracker.tracks[agent].steps if s.decision is not None]
            read = [names[s.decision[2]] for s in steps if s.decision is not None]
            made = expected_reading(person, tracker, cells[agent], steps[0].tick if steps else 0)
            # an action the world does not allow is carried out as a Stay, and read as one;
            # the last decision may still be under way
            i = next(
                (i for i, (m, r) in enumerate(zip(made, read, strict=False)) if m != r and r != "stay"), None
            )
            assert i is None and len(made) - len(read) in (0, 1), (
                f"seed {seed}, {agent}: expected the tracker to read {made[max(0, (i or 0) - 3) :][:8]}, "
                f"it read {read[max(0, (i or 0) - 3) :][:8]} (from decision {max(0, (i or 0) - 3)}; "
                f"{len(made)} made, {len(read)} read)"
            )
            done = made[: len(read)]  # the last one made may still be under way (above)
            assert read.count("stay") >= done.count("stay") >= 5, (
                f"seed {seed}, {agent}: {done.count('stay')} Stays made (and done), {read.count('stay')} read"
            )
            in_a_row += sum(a == b == "stay" for a, b in zip(made, made[1:], strict=False))
    assert in_a_row > 5, f"expected Stays in a row to be tested, got {in_a_row}"
