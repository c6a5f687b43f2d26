"""A person's answer to the robot's ``ask`` (protocol 1.6) is evidence about what they want,
in every form of the person model: real sim2d, real commands, A1 (who wants the skate) asked
by the robot; the brain reads the ``answer`` events from the engine alone."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from support import one_person, run_command

from brain.model.answers import answer_likelihood
from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from protocol import Action, Ask, Cell, CommandState, Navigate
from sim2d.engine import Engine

FORMS = {
    "graded": ModelSettings(),
    "graded-factored": ModelSettings(exact_max_worlds=1),
    "point": ModelSettings(belief_model="point"),
    "point-factored": ModelSettings(belief_model="point", exact_max_worlds=1),
    "lapses": ModelSettings(miss=0.2),
}


def test_an_answer_is_evidence_with_its_reliability_not_an_overwrite() -> None:
    yes = answer_likelihood(3, 1, True, 0.9)
    assert yes.tolist() == pytest.approx([0.05, 0.9, 0.05]), yes
    no = answer_likelihood(3, 1, False, 0.9)
    assert no.tolist() == pytest.approx([0.9, 0.1, 0.9]), no
    nothing = answer_likelihood(3, None, False, 0.9)
    assert nothing.tolist() == pytest.approx([0.05, 0.05, 0.9]), nothing


def _ask(engine: Engine, tracker: MindTracker, action: Action) -> None:
    statuses = run_command(engine, action, tracker)
    assert statuses[-1].state is CommandState.SUCCEEDED, f"{action}: {statuses[-1]}"


@pytest.mark.parametrize("form", sorted(FORMS))
def test_what_a_person_answers_moves_the_estimate_of_what_they_want(tmp_path: Path, form: str) -> None:
    engine = Engine(str(one_person(tmp_path, "asked", a1=(5, 5), robot=(7, 5))))
    tracker = MindTracker(engine.scene(), FORMS[form])
    tracker.observe(engine.state(), ())
    skate, ball = tracker.model.items.index("skate"), tracker.model.items.index("ball")
    _ask(engine, tracker, Navigate(cell=Cell(6, 5)))
    before = tracker.online("A1")
    assert before is not None
    _ask(engine, tracker, Ask(person="A1", item="ball"))  # "no"
    after_no = tracker.online("A1")
    assert after_no is not None and after_no.preference[ball] < before.preference[ball] - 0.1, (
        f"{form}: A1 said no to the ball: P(ball) {before.preference[ball]:.3f} -> "
        f"{after_no.preference[ball]:.3f}, expected it to fall"
    )
    _ask(engine, tracker, Ask(person="A1"))  # "the skate"
    after = tracker.online("A1")
    assert after is not None and after.preference[skate] > 0.8, (
        f"{form}: A1 said they want the skate: P(skate) {after.preference[skate]:.3f}, expected > 0.8 "
        f"(before asking {before.preference[skate]:.3f})"
    )
    assert after.preference[skate] < 0.999, (
        f"{form}: an answer is evidence, not certainty: {after.preference}"
    )
    assert np.isclose(after.preference.sum(), 1.0)
