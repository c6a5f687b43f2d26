"""A desire that survives a pause: at each decision the preference may be redrawn from the
prior (which may keep it). Compounded over ``n`` decision times it is ``H^n``, which tends to
the prior (or a person's remembered desires). The rule before put ``1 - (1 - h)^n`` on the
*other* preferences, so after a long pause a change was near-certain and, with two goals, a
flip certain."""

from __future__ import annotations

import numpy as np

from brain.model.inference import hazard_matrix, switch_probability, switched
from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from tests.brain.memory.test_days import a_day_with_the_ball, day_end, preference
from tests.scenes import household_scene, household_state


def test_the_switch_compounds_exactly_and_tends_to_the_prior() -> None:
    for goals in (2, 3, 5):
        one = hazard_matrix(goals, 0.05)
        for n in (1, 7, 40):
            power = np.linalg.matrix_power(one, n)
            exact = hazard_matrix(goals, switch_probability(0.05, n))
            assert np.allclose(power, exact), f"H^{n} with {goals} goals is not H(1 - (1 - h)^{n})"
        long = np.linalg.matrix_power(one, 2000)
        assert np.allclose(long, 1 / goals), f"H^n with {goals} goals does not tend to the uniform prior"
    sure = np.array([1.0, 0.0])
    after = switched(sure, switch_probability(0.05, 1000))
    assert abs(after[0] - 0.5) < 1e-6, (
        f"with two goals a near-certain redraw leaves 1/2 on the first, got {after[0]:.3f} (a flip gives 0)"
    )


def test_a_person_back_from_a_long_errand_wants_their_remembered_favourite() -> None:
    """Day 2 of p, remembered (day 1) to want the ball: from R1 they walk out through R2 to
    the outside, stay 180 ticks (126 s, 180 decision times at 0.7 s) and step back in. The
    walk out reads as wanting to leave (every toy near the likelihood's floor outside), and
    the long pause redraws toward the remembered desires: P(ball) on the step back is
    within 0.1 of P(ball) when they left (their first tick of the day). Without a memory
    the redraw is even (the toys 0.5 each), which is all a stranger's errand can give."""
    settings = ModelSettings()
    day1, last = a_day_with_the_ball(settings)
    for memory, expected in ((day_end(day1, last), None), (None, 0.5)):
        tracker = MindTracker(household_scene(), settings, memory=memory)
        tick = 0
        for tick, cell in enumerate(((1, 0), (2, 0), (3, 0), (4, 0), (5, 0), (5, 1), (5, 2))):
            tracker.observe(household_state(tick, cell), [])
            if tick == 0:
                left = preference(tracker, "ball")
        for _ in range(180):
            tick += 1
            tracker.observe(household_state(tick, (5, 2)), [])
        tracker.observe(household_state(tick + 1, (5, 1)), [])
        back = preference(tracker, "ball")
        want = left if expected is None else expected
        assert abs(back - want) <= 0.1, (
            f"expected P(ball) back from a 180-tick errand within 0.1 of {want:.2f} "
            f"({'when they left' if expected is None else 'no memory: even'}), got {back:.2f}"
        )
