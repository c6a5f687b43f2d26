"""The item-value encoding has one home (:mod:`protocol.itemvalue`): the brain's model encodes
with it and the engine's planned people decode the brain's policy table with it."""

from __future__ import annotations

import numpy as np

from brain.model import world as brain_world
from protocol import itemvalue
from protocol.itemvalue import (
    HELD,
    RESTING,
    held_value,
    is_held,
    is_resting,
    location_of,
    value_count,
    value_of,
)
from sim2d.people import planned


def test_a_value_names_a_location_and_whether_the_item_is_held() -> None:
    for location in range(5):
        for held in (False, True):
            value = value_of(location, held)
            assert (location_of(value), is_held(value), is_resting(value)) == (location, held, not held)
            assert held_value(value) == value_of(location, True)
    assert value_count(4) == 8


def test_the_halves_of_an_axis_of_values_are_the_resting_and_the_held() -> None:
    values = np.arange(value_count(3), dtype=np.int64)
    assert values[RESTING].tolist() == [value_of(loc) for loc in range(3)]
    assert values[HELD].tolist() == [value_of(loc, True) for loc in range(3)]
    locations = np.array([0, 2, 1], dtype=np.int64)
    held = np.array([True, False, True])
    assert value_of(locations, held).tolist() == [1, 4, 3]
    assert is_held(value_of(locations, held)).tolist() == held.tolist()


def test_the_brain_and_the_engine_use_the_one_encoding() -> None:
    for name in ("value_of", "location_of", "is_held", "is_resting", "held_value", "RESTING", "HELD"):
        assert getattr(brain_world, name) is getattr(itemvalue, name), f"brain.model.world.{name} is its own"
    assert planned.value_of is value_of and planned.HELD is HELD and planned.RESTING is RESTING
