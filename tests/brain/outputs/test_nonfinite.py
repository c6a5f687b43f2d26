"""Issue 49, item 3: a non-finite number in the model's output stops the brain with an error
naming the person, the quantity and the tick, instead of a ``mind`` message every subscriber
drops (``dropped: invalid mind message``) or NaN rows in ``mind.csv``."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from brain.errors import NonFiniteError
from brain.outputs.results import mind_message, write_outputs
from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from sim2d.engine import Engine
from tests.scenes import corridor_scene, corridor_state


def _tracker() -> MindTracker:
    tracker = MindTracker(corridor_scene(), ModelSettings())
    for tick, cell in enumerate((5, 5, 6, 7)):
        tracker.observe(corridor_state(tick, cell), [])
    return tracker


def test_a_nan_probability_in_the_estimate_stops_the_mind_message() -> None:
    tracker = _tracker()
    est = tracker.online("p")
    assert est is not None, "expected an estimate of 'p' after four ticks"
    est.preference[0] = np.nan  # the fault: what an overflowing softmax left behind
    with pytest.raises(NonFiniteError) as caught:
        mind_message(tracker, corridor_state(3, 7))
    message = str(caught.value)
    assert (
        "'p' at tick 3: the model's preference not finite" in message
        and "nan" in message
        and "\n" not in message
    ), f"expected one line naming the person, the quantity, the tick and the value, got {message!r}"


@pytest.mark.filterwarnings("ignore::RuntimeWarning")
def test_an_overflowing_model_writes_no_nan_rows_to_mind_csv(tmp_path: Path) -> None:
    """The settings refuse ``beta=1e308`` now; a model whose numbers overflow anyway (here:
    that beta forced past the check) fails the outputs instead of writing NaN rows."""
    settings = ModelSettings()
    object.__setattr__(settings, "beta", 1e308)  # the fault, past the settings' own check
    engine = Engine("sally-anne")
    tracker = MindTracker(engine.scene(), settings)
    result = engine.reset()
    for _ in range(40):  # NaN from tick 15 on (the run: a live table stuck at tick 14)
        tracker.observe(result.state, result.events)
        result = engine.step()
    with pytest.raises(NonFiniteError, match=r"'sally' at tick \d+: the model's"):
        write_outputs(tracker, "sally-anne", tmp_path)
    assert not (tmp_path / "mind.csv").exists(), "expected no mind.csv written with non-finite rows"
