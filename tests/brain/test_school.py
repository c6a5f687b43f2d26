"""Two defects an engine written from the docs alone showed, in a school (issue 36): people
who had never seen an item were flagged as holding a false belief about it, and an item
carried through a hallway (a region without locations) was seen from a classroom whose
location it counts at. Built in-process on :func:`tests.scenes.school_scene`."""

from __future__ import annotations

import pytest

from brain.model.belief import NOT_IN_VIEW
from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from tests.scenes import school_scene, school_state

OUT_OF_C0 = [(1, 1), (1, 2), (1, 3), (1, 4), (2, 4), (3, 4)]
"""Ann leaves her classroom C0 for the hallway."""


@pytest.mark.parametrize(
    ("spots", "items", "people", "exact"),
    [
        ((4, 4, 4, 4), ("backpack", "book", "ball"), ("ann", "bob", "cat"), False),
        ((1, 11), ("book", "ball"), ("ann",), True),
    ],
    ids=["factored-16-locations", "exact-12-locations"],
)
def test_an_item_never_seen_is_no_false_belief(
    spots: tuple[int, ...], items: tuple[str, ...], people: tuple[str, ...], exact: bool
) -> None:
    """Ann sees only her classroom's spots, and never the book or the ball (in the last
    classroom). Before behaviour says anything, P(false belief) about them must stay well
    below 0.5 from the first tick on: it was 0.94 on 16 locations (a belief spread evenly
    over the 12 places she could not see gives each less than 0.1, and the grid's points
    that exclude the truth are most of the grid), and 0.92 on 12 (11 unseen)."""
    scene = school_scene(spots, items, people)
    tracker = MindTracker(scene, ModelSettings(exact_max_worlds=600 if exact else 512))
    assert tracker.exact is exact
    last = f"C{len(spots) - 1}"
    where = {item: f"{last}.{k}" for k, item in enumerate(items)}
    where.setdefault("backpack", "C0.0")  # her own, in view
    unseen = [k for k, item in enumerate(tracker.model.items) if item in ("book", "ball")]
    for tick, cell in enumerate(OUT_OF_C0):
        tracker.observe(school_state(scene, tick, {"ann": cell}, where), [])
        est = tracker.online("ann")
        assert est is not None
        p = est.false_belief[unseen]
        bound = (1 - tracker.settings.ignorance) * tracker.settings.stale_share
        assert tick > 0 or p.max() <= bound + 1e-9, f"first tick: P(false belief) {p}, bound {bound}"
        assert p.max() < 0.4, f"tick {tick}, ann on {cell}: P(false belief) about items never seen {p}"
        assert not set(est.false_beliefs) & set(unseen), f"tick {tick}: flagged {est.false_beliefs}"


def test_walking_straight_past_the_item_to_a_wrong_room_raises_a_false_belief() -> None:
    """The ``stale`` case: ann wants the book (she takes nothing, leaves her room and walks
    on), which rests in C1; she walks past C1's door towards C2, as someone sure it is in C2
    does. Behaviour must still raise P(false belief) above 0.5, before she reaches C2 (where
    she would see it is not there)."""
    scene = school_scene((4, 4, 4), ("book", "ball"))
    tracker = MindTracker(scene, ModelSettings())
    where = {"book": "C1.0", "ball": "C0.1"}
    route = [*OUT_OF_C0, *[(c, 4) for c in range(4, 12)]]  # along the hallway to C2's door (11, 3)
    book = tracker.model.items.index("book")
    p = []
    for tick, cell in enumerate(route):
        tracker.observe(school_state(scene, tick, {"ann": cell}, where), [])
        est = tracker.online("ann")
        assert est is not None
        p.append(round(float(est.false_belief[book]), 3))
    assert max(p[:6]) < 0.4, f"before she passes C1: {p}"
    assert p[-1] > 0.5, f"P(false belief about the book) along the hallway: {p}"


def test_an_item_carried_through_the_hallway_is_seen_only_by_those_who_see_its_carrier() -> None:
    """Bob carries the book from C1 along the hallway, which has no locations, so it counts
    at the nearest location of all: C0.1, in ann's classroom. Ann, in C0, does not see Bob
    and must not perceive the book (she did: "held near C0.1", and believed it there); cat,
    in the hallway, sees Bob carrying it."""
    scene = school_scene()
    tracker = MindTracker(scene, ModelSettings())
    model = tracker.model
    book = model.items.index("book")
    items = {"backpack": "C0.0", "book": "C1.0", "ball": "C2.0"}
    tracker.observe(school_state(scene, 0, {"cat": (3, 4)}, items), [])
    route = [(6, 1), (6, 2), (6, 3), (6, 4), (5, 4), (4, 4), (3, 4), (2, 4), (1, 4)]
    carrying = {**items, "book": "bob"}
    for tick, cell in enumerate(route, start=1):
        tracker.observe(school_state(scene, tick, {"bob": cell, "cat": (3, 4)}, carrying), [])
    truth = tracker.truth[book]
    assert model.locations[truth // 2] == "C0.1" and truth % 2 == 1, "carried, counted at C0.1"
    ann = tracker.tracks["ann"].chains[0].percept
    cat = tracker.tracks["cat"].chains[0].percept
    assert ann is not None and cat is not None
    assert ann.seen[book] == NOT_IN_VIEW, "ann cannot see bob in the hallway"
    assert cat.seen[book] == truth, "cat, in the hallway, sees bob carrying the book"
    est = tracker.online("ann")
    assert est is not None
    c01 = model.locations.index("C0.1")
    assert est.beliefs[book, c01] < 0.05, f"ann believes the book at C0.1: {est.beliefs[book, c01]:.2f}"
