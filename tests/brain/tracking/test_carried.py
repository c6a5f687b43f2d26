"""What a person believes of an item they see carried (issue 52): held by its carrier, not
resting where they saw it pass. A1 stands in S1 or S2 of the paper map while the robot (real
sim2d, real commands) picks the ball up at S1 and carries it east; the brain reads A1 from
the engine's states alone."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from support import one_person, run_command

from brain.model.world import is_held
from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from protocol import Action, Cell, CommandState, Navigate, Pick, Place
from sim2d.engine import Engine


class Watch:
    """The engine and the brain's tracker, stepped together; A1's ball as the brain reads it."""

    def __init__(self, tmp_path: Path, home: tuple[int, int]) -> None:
        self.engine = Engine(str(one_person(tmp_path, "carried", a1=home, robot=(6, 5))))
        self.tracker = MindTracker(self.engine.scene(), ModelSettings())
        self.tracker.observe(self.engine.state(), ())
        self.ball = self.tracker.model.items.index("ball")

    def run(self, action: Action) -> None:
        """One robot command, stepped until it ends; it must succeed."""
        statuses = run_command(self.engine, action, self.tracker)
        assert statuses[-1].state is CommandState.SUCCEEDED, f"{action}: {statuses[-1]}"

    def a1(self) -> tuple[dict[str, float], float, float]:
        """A1's ball: P(believed at each location), P(believed held by someone), and the
        brain's P(A1's belief is false)."""
        est = self.tracker.online("A1")
        assert est is not None and est.worlds is not None
        model = self.tracker.model
        held = float(est.worlds[is_held(model.worlds[:, self.ball])].sum())
        where = dict(zip(model.locations, np.round(est.beliefs[self.ball], 3).tolist(), strict=True))
        return where, held, float(est.false_belief[self.ball])


def test_a_person_who_watches_the_robot_carry_an_item_believes_it_held_then_where_it_is_put(
    tmp_path: Path,
) -> None:
    watch = Watch(tmp_path, (9, 10))  # A1 in S2
    watch.run(Navigate(cell=Cell(5, 9)))
    watch.run(Pick(item="ball"))
    watch.run(Navigate(cell=Cell(9, 9)))  # into S2, before A1's eyes
    where, held, _ = watch.a1()
    assert held > 0.99 and where["S2"] > 0.99, (
        f"A1 sees the robot holding the ball in S2: got {where}, held {held}"
    )
    watch.run(Place(location="S2"))
    where, held, false = watch.a1()
    assert held < 0.01 and where["S2"] > 0.99 and false < 0.01, (
        f"A1 saw the ball put down at S2: expected it resting there, got {where}, held {held}, false {false}"
    )


def test_an_item_carried_off_out_of_sight_is_not_believed_where_it_was_seen_passing(tmp_path: Path) -> None:
    """A1 waits in the entrance hall, which has no item location: a ball carried through it
    counts at the nearest location (S1 or S2), which A1 cannot see from there. Before, A1 went
    on believing it there (p = 1.0) once the robot had carried it off, a false belief as soon
    as the robot put it down elsewhere (``gen-paper-s202027``)."""
    watch = Watch(tmp_path, (6, 5))
    watch.run(Navigate(cell=Cell(5, 9)))
    watch.run(Pick(item="ball"))
    watch.run(Navigate(cell=Cell(8, 5)))  # through the hall, before A1's eyes
    where, held, _ = watch.a1()
    passing = max(where, key=lambda loc: where[loc])
    assert held > 0.99 and where[passing] > 0.99, (
        f"A1 sees the robot carry the ball: got {where}, held {held}"
    )
    watch.run(Navigate(cell=Cell(13, 8)))  # out of the hall, across to P2
    where, held, _ = watch.a1()
    assert held > 0.99 and where[passing] < 0.5, (
        f"the robot went out of sight with the ball: A1 believes it held anywhere out of sight, not at "
        f"{passing}; got {where}, held {held}"
    )
    watch.run(Place(location="P2"))
    where, _, false = watch.a1()
    assert false < 0.5 and where["P2"] == pytest.approx(max(where.values())), (
        f"put down at P2 out of A1's sight: A1 does not know where, but believes nothing false of it; "
        f"got {where}, false-belief probability {false:.3f}"
    )
