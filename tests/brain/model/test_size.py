"""Issue 49, item 4: the brain refuses a scene whose model would not fit
(:data:`brain.model.size.MAX_MODEL_BYTES`) in one line, before allocating it; before, 1,000
items made it try to allocate 4.59 GiB (and die of a ``MemoryError`` traceback). The figure
it goes by is the model's real size, measured, within a factor of two. Issue 53, item 2: an
embodied robot's branches of the unseen world, times the people, times their lapse rows, that
could not fit in :data:`brain.model.size.MEMORY_BUDGET_GB` even at their smallest are refused
at the first look, before any of their filters is made."""

from __future__ import annotations

import resource
import time
import tracemalloc
from pathlib import Path

import msgspec
import numpy as np
import pytest

from brain.errors import ModelTooLarge
from brain.model.size import MAX_MODEL_BYTES, MEMORY_BUDGET_GB, factored_rows, model_size, row_floor
from brain.settings import ModelSettings, UnseenWorld
from brain.tracking.itemworld import ItemWorld
from brain.tracking.tracker import MindTracker
from protocol import ItemSpec
from sim2d.engine import Engine
from sim2d.generation import write_house_episode


def test_a_thousand_items_are_refused_before_anything_is_allocated() -> None:
    scene = Engine("sally-anne").scene()
    scene = msgspec.structs.replace(scene, items=tuple(ItemSpec(id=f"i{k}") for k in range(1000)))
    before, start = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss, time.monotonic()
    with pytest.raises(ModelTooLarge) as caught:
        MindTracker(scene, ModelSettings())
    grown_mb = (resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before) / 1024
    message = str(caught.value)
    assert message.startswith("scene 'sally-anne': the model's arrays would take") and "\n" not in message, (
        f"expected one line naming the scene and the size, got {message!r}"
    )
    assert "above the brain's limit of 2 GiB" in message, message
    assert time.monotonic() - start < 10 and grown_mb < 200, (
        f"expected a refusal before allocating (< 10 s, < 200 MB), took {time.monotonic() - start:.1f} s, "
        f"{grown_mb:.0f} MB more"
    )


def test_the_largest_generated_house_is_well_within_the_limit(tmp_path: Path) -> None:
    """``toyroom bench``'s largest house (20 rooms, 10 items, 8 people) stays under a tenth."""
    from sim2d.generation import write_house_episode

    scene = Engine(str(write_house_episode(tmp_path, 20, 10, 0, people=8))).scene()
    size = model_size(scene, ModelSettings())
    assert size.form == "factored" and size.bytes < MAX_MODEL_BYTES / 10, f"got {size}"


@pytest.mark.parametrize(("scenario", "belief_model"), [("paper-1", "graded"), ("food-trucks", "graded")])
def test_the_figure_is_the_model_measured_within_a_factor_of_two(scenario: str, belief_model: str) -> None:
    engine = Engine(scenario)
    # a vi_tolerance of its own: its own planner, not one cached by an earlier test
    settings = ModelSettings(belief_model=belief_model, vi_tolerance=1.5e-9)
    tracemalloc.start()
    try:
        tracker = MindTracker(engine.scene(), settings)
        result = engine.reset()
        for _ in range(20):
            tracker.observe(result.state, result.events)
            result = engine.step()
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    estimate = model_size(engine.scene(), settings).bytes
    assert peak / 2 <= estimate <= peak * 2, (
        f"{scenario}: estimated {estimate:,} bytes, measured a peak of {peak:,}"
    )


@pytest.fixture(scope="module")
def twenty_rooms(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A generated house of 20 rooms and 3 items: 5832 branches of the unseen world at an
    embodied robot's first look."""
    return write_house_episode(tmp_path_factory.mktemp("house20"), 20, 3, 1)


def test_branches_lapses_and_people_beyond_the_memory_budget_are_refused_at_the_first_look(
    twenty_rooms: Path,
) -> None:
    engine = Engine(str(twenty_rooms))
    joint = ModelSettings(perception="embodied", miss=0.2, unseen_world=UnseenWorld.JOINT)
    tracker = MindTracker(engine.scene(), joint)
    before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    with pytest.raises(ModelTooLarge) as caught:
        tracker.observe(engine.state(), ())
    grown_mb = (resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before) / 1024
    message = str(caught.value)
    for part in (
        "5832 branches of the unseen world",
        "2 people",
        "16 lapse rows",
        f"{MEMORY_BUDGET_GB:.0f} GiB",
    ):
        assert part in message, f"expected {part!r} in the refusal, got: {message}"
    assert grown_mb < 200, f"the refusal came after {grown_mb:.0f} MB were allocated"
    small = write_house_episode(twenty_rooms.parent, 8, 3, 1)
    engine = Engine(str(small))
    ok = MindTracker(engine.scene(), ModelSettings(perception="embodied", miss=0.2))
    ok.observe(engine.state(), ())  # 36 branches x 2 people x 16 rows x 17.8 kB: accepted
    assert ok.view is not None and len(ok.view.rows) == 36, len(ok.view.rows) if ok.view else None


def test_the_scene_refused_with_joint_branches_runs_factored(twenty_rooms: Path) -> None:
    """Issue 66, item 2: by default (``unseen_world = auto``) the 20-room, 3-item house the
    joint branches cannot hold looks with the factored world, within the budget, and follows
    its people."""
    engine = Engine(str(twenty_rooms))
    tracker = MindTracker(engine.scene(), ModelSettings(perception="embodied", miss=0.2))
    tracker.observe(engine.state(), ())
    assert isinstance(tracker.world, ItemWorld) and tracker.view is None
    for _ in range(40):
        out = engine.step()
        tracker.observe(out.state, out.events)
    where = tracker.where()
    assert where is not None and np.allclose(where.sum(axis=1)[where.sum(axis=1) > 0], 1.0)
    assert any(tracker.online(p) is not None for p in tracker.people)
    people, rows = len(tracker.people), 16  # lapse rows
    assert (
        factored_rows(engine.scene(), tracker.settings, tracker.person_model, 64)
        * people
        * rows
        * (row_floor(engine.scene(), tracker.settings))
        <= MEMORY_BUDGET_GB * 2**30
    )


def test_the_floor_of_a_row_is_the_factored_filters_arrays(twenty_rooms: Path) -> None:
    """The factored rows hold exactly the arrays :func:`row_floor` counts (the exact model's
    hold more: a floor)."""
    small = write_house_episode(twenty_rooms.parent, 8, 3, 1)
    engine = Engine(str(small))
    settings = ModelSettings(perception="embodied")
    tracker = MindTracker(engine.scene(), settings)
    tracker.observe(engine.state(), ())
    for _ in range(30):
        out = engine.step()
        tracker.observe(out.state, out.events)
    filters = [c.filter for t in tracker.tracks.values() for c in t.chains if c.filter is not None]
    assert filters, "nobody was seen in 30 ticks"
    held = {f.alpha.nbytes + f.weights.nbytes + f.beliefs.nbytes for f in filters}  # type: ignore[union-attr]
    floor = row_floor(engine.scene(), settings)
    assert all(floor <= h <= floor + 64 for h in held), f"rows hold {held} bytes, the floor says {floor}"
