"""The names of an item's value (``brain/model/world.py``): ``2 * location + held``, on ints
and elementwise on int64 arrays, and the slices of a value axis."""

from __future__ import annotations

import numpy as np

from brain.model.world import (
    HELD,
    RESTING,
    VALUES_PER_LOCATION,
    held_value,
    is_held,
    is_resting,
    location_of,
    value_of,
)


def test_an_int_value_round_trips() -> None:
    for location in range(5):
        for held in (False, True):
            value = value_of(location, held=held)
            assert type(value) is int, f"value_of({location}, {held}) is a {type(value)}, expected an int"
            got = (location_of(value), is_held(value), is_resting(value))
            assert got == (location, held, not held), (
                f"value {value}: expected (location, held, resting) {(location, held, not held)}, got {got}"
            )
            assert held_value(value) == value_of(location, held=True), (
                f"held_value({value}) is {held_value(value)}, expected {value_of(location, held=True)}"
            )


def test_the_encoding_is_two_per_location() -> None:
    expected = [2 * 3, 2 * 3 + 1]
    got = [value_of(3), value_of(3, held=True)]
    assert got == expected, f"values of location 3 (resting, held): expected {expected}, got {got}"
    assert VALUES_PER_LOCATION == 2, f"expected 2 values per location, got {VALUES_PER_LOCATION}"


def test_arrays_round_trip_elementwise() -> None:
    locations = np.array([[0, 1, 2], [3, 4, 5]], dtype=np.int64)
    held = np.array([[True, False, True], [False, False, True]])
    values = value_of(locations, held=held)
    assert values.dtype == np.int64, f"values of int64 locations: expected int64, got {values.dtype}"
    assert values.shape == locations.shape, f"expected shape {locations.shape}, got {values.shape}"
    np.testing.assert_array_equal(location_of(values), locations, err_msg="location_of(value_of(l, h))")
    np.testing.assert_array_equal(is_held(values), held, err_msg="is_held(value_of(l, h))")
    np.testing.assert_array_equal(is_resting(values), ~held, err_msg="is_resting(value_of(l, h))")
    np.testing.assert_array_equal(
        held_value(values), value_of(locations, held=True), err_msg="held_value(value_of(l, h))"
    )
    np.testing.assert_array_equal(value_of(locations), 2 * locations, err_msg="value_of(l) resting")


def test_the_slices_pick_resting_and_held_values_in_location_order() -> None:
    values = np.arange(VALUES_PER_LOCATION * 4)
    np.testing.assert_array_equal(values[RESTING], value_of(np.arange(4)), err_msg="values[RESTING]")
    np.testing.assert_array_equal(values[HELD], value_of(np.arange(4), held=True), err_msg="values[HELD]")
