"""Issue 49, item 4: the brain refuses a scene whose model would not fit
(:data:`brain.model.size.MAX_MODEL_BYTES`) in one line, before allocating it; before, 1,000
items made it try to allocate 4.59 GiB (and die of a ``MemoryError`` traceback). The figure
it goes by is the model's real size, measured, within a factor of two."""

from __future__ import annotations

import resource
import time
import tracemalloc
from pathlib import Path

import msgspec
import pytest

from brain.errors import ModelTooLarge
from brain.model.size import MAX_MODEL_BYTES, model_size
from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from protocol import ItemSpec
from sim2d.engine import Engine


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
