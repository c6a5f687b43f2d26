"""A simulated person's own belief: the update on a percept, and its shortcut for a percept
met again."""

from __future__ import annotations

import numpy as np

from sim2d.people.belief import PersonBelief

LOCATIONS = ["S1", "S2", "S3", "S4"]


def _fresh(p: np.ndarray) -> PersonBelief:
    belief = PersonBelief(["ball", "book"], LOCATIONS)
    belief.p = p.copy()
    return belief


def test_a_percept_moves_unseen_mass_out_of_view_and_pins_what_is_seen() -> None:
    belief = PersonBelief(["ball", "book"], LOCATIONS)
    belief.perceive(("S1", "S2"), {"ball": "S2"})
    assert belief.of("ball").tolist() == [0.0, 1.0, 0.0, 0.0]
    assert belief.of("book").tolist() == [0.0, 0.0, 0.5, 0.5], "the book is not in view: S3 or S4"
    belief.perceive(("S3", "S4"), {})
    assert belief.of("book").tolist() == [0.5, 0.5, 0.0, 0.0], "believed in view but gone: out of view"
    belief.perceive(("S1", "S2"), {"book": "S1"}, missed={"ball"})
    assert belief.of("ball").tolist() == [0.0, 1.0, 0.0, 0.0], "a missed item keeps its belief"
    assert belief.of("book").tolist() == [1.0, 0.0, 0.0, 0.0]
    belief.perceive(("S1", "S2"), {"book": "S1"})
    assert belief.of("ball").tolist() == [0.0, 0.0, 0.5, 0.5], "noticed gone from S2: out of view"


def test_the_same_percept_met_again_gives_what_the_arithmetic_gives() -> None:
    rng = np.random.default_rng(4)
    belief = PersonBelief(["ball", "book"], LOCATIONS)
    for _ in range(30):
        visible = tuple(loc for loc in LOCATIONS if rng.random() < 0.5)
        seen = {"ball": "S1"} if "S1" in visible and rng.random() < 0.5 else {}
        for _ in range(3):  # standing still: the same percept, tick after tick
            reference = _fresh(belief.p)
            reference.perceive(visible, seen)
            belief.perceive(visible, seen)
            assert belief.p.tobytes() == reference.p.tobytes(), (visible, seen, belief.p, reference.p)
        belief.told("book", "S4")  # the belief changed under the same percept: computed again
        reference = _fresh(belief.p)
        reference.perceive(visible, seen)
        belief.perceive(visible, seen)
        assert belief.p.tobytes() == reference.p.tobytes()
