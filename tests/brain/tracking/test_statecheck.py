"""A state that does not say where every item is: a clear error naming the item, and the
tracker keeps following the states that do."""

from __future__ import annotations

import msgspec
import pytest

from brain.errors import StateError
from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from protocol import Observer
from tests.scenes import tiny_scene, tiny_state


def test_a_state_without_an_item_is_named_and_skipped() -> None:
    tracker = MindTracker(tiny_scene(), ModelSettings(), Observer.BTOM)
    tracker.observe(tiny_state(0, (4, 0), "A"), ())
    good = tiny_state(1, (3, 0), "A")
    cases = {
        "lists no item 'ball'": msgspec.structs.replace(good, items=()),
        "neither held nor resting": msgspec.structs.replace(
            good, items=(msgspec.structs.replace(good.items[0], location=None),)
        ),
        "held by 'ghost'": msgspec.structs.replace(
            good, items=(msgspec.structs.replace(good.items[0], location=None, held_by="ghost"),)
        ),
    }
    for says, bad in cases.items():
        with pytest.raises(StateError, match=says):
            tracker.observe(bad, ())
    assert tracker.ticks == [0], f"a refused state was taken in: ticks {tracker.ticks}"
    tracker.observe(good, ())
    assert tracker.ticks == [0, 1]
