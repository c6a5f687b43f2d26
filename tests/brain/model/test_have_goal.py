"""Wishes read where locations are only for storing (issue 39): in a scene with no play and
no ``use`` location, taking an item is the goal ("have it"), so a person heading for their
backpack and taking it shows that they want it. Scenes with play or use locations keep their
goals (the paper's numbers and the food trucks' are unchanged: their tests say so)."""

from __future__ import annotations

import numpy as np
import pytest

from brain.model.planner import HAVE, TAKE, transitions
from brain.model.world import build_world_model
from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from protocol import (
    AgentKind,
    AgentSpec,
    Cell,
    Event,
    EventKind,
    ItemSpec,
    Location,
    Region,
    RegionKind,
    Scene,
    Vec2,
    Visibility,
)
from tests.scenes import school_state, tiny_scene

ROOM = tuple(Cell(c, r) for r in range(3) for c in range(7))
SPOTS = {"hooks": Cell(0, 1), "desk": Cell(6, 1), "shelf": Cell(3, 2)}
WHERE = {"backpack": "hooks", "book": "desk", "ball": "shelf"}


def cloakroom() -> Scene:
    """A 7 x 3 classroom whose three locations (hooks on the west wall, a desk on the east,
    a shelf at the north) are for storing only: no play spot, no use, no outside. Everyone
    sees every location; the person starts in the middle of the south row."""
    return Scene(
        name="cloakroom",
        cell_size=1.0,
        origin=Vec2(0.0, 0.0),
        columns=7,
        rows=3,
        regions=(Region(id="C", kind=RegionKind.ROOM, cells=ROOM),),
        doors=(),
        locations=tuple(Location(id=i, region="C", cell=c) for i, c in SPOTS.items()),
        visibility=tuple(Visibility(cell=c, locations=tuple(SPOTS)) for c in ROOM),
        agents=(AgentSpec(id="ann", kind=AgentKind.PERSON, home=Cell(3, 0)),),
        items=tuple(ItemSpec(id=i) for i in WHERE),
    )


def heads_for_the_backpack(settings: ModelSettings) -> MindTracker:
    """Ann walks west to the hooks and takes her backpack."""
    scene = cloakroom()
    tracker = MindTracker(scene, settings)
    path = [(3, 0), (2, 0), (1, 0), (0, 0), (0, 1)]
    for tick, cell in enumerate(path):
        tracker.observe(school_state(scene, tick, {"ann": cell}, WHERE), ())
    tick = len(path)
    take = Event(
        episode=1,
        tick=tick,
        time=tick * 0.7,
        kind=EventKind.TAKE,
        actor="ann",
        item="backpack",
        location="hooks",
    )
    tracker.observe(school_state(scene, tick, {"ann": (0, 1)}, {**WHERE, "backpack": "ann"}), (take,))
    return tracker


def test_taking_is_the_goal_only_where_nothing_else_can_be_done_with_an_item() -> None:
    model = build_world_model(cloakroom())
    assert model.have_goals
    trans = transitions(model)
    takes = trans.terminal_kind[:, TAKE : TAKE + model.n_items]
    assert (takes == HAVE).any(), "no Take ends the episode in a storage-only scene"
    paper = build_world_model(tiny_scene())  # a play spot: taking is a step, playing the goal
    assert not paper.have_goals
    assert not (transitions(paper).terminal_kind == HAVE).any()


@pytest.mark.parametrize(
    "settings",
    [
        ModelSettings(),
        ModelSettings(desire_model="graded"),
        ModelSettings(belief_model="point"),
        ModelSettings(exact_max_worlds=1),
    ],
    ids=["graded-beliefs", "graded-desires", "point", "factored"],
)
def test_heading_for_an_item_and_taking_it_shows_the_wish(settings: ModelSettings) -> None:
    """Before: uniform 0.33 over the items (there was nothing to want an item for). Now the
    backpack's P(most wanted) is above 0.8 once she has taken it, and it rose on the way."""
    tracker = heads_for_the_backpack(settings)
    backpack = tracker.model.items.index("backpack")
    estimates = tracker.tracks["ann"].estimates
    online = [float(e.preference[backpack]) for e in estimates]
    assert online[-1] > 0.8, f"P(backpack most wanted) after the take: expected > 0.8, got {online[-1]:.3f}"
    assert online[-2] > online[0] + 0.1, f"expected the walk west to raise it, got {np.round(online, 3)}"
    if tracker.exact:
        smoothed = tracker.smoothed("ann")
        assert float(smoothed[0].preference[backpack]) > 0.8, smoothed[0].preference
