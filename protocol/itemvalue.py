"""The item-value encoding: where an item is, as one integer, shared by the brain's model and
the engine's planned people (which read the brain's policy table).

An item's value ``v = 2 l + held`` names location index ``l`` (in the scene's location
order) and whether the item rests there (``held`` 0) or is held by someone near it (1): ``V =
2L`` values per item. Nobody writes this arithmetic by hand: :func:`value_of` encodes,
:func:`location_of`, :func:`is_held` and :func:`is_resting` decode, :data:`RESTING` and
:data:`HELD` pick either half of an axis of ``V`` values, and :func:`value_count` gives ``V``.
Every function is also elementwise on int64 numpy arrays.
"""

from __future__ import annotations

from typing import overload

import numpy as np
import numpy.typing as npt

IntArray = npt.NDArray[np.int64]
BoolArray = npt.NDArray[np.bool_]

VALUES_PER_LOCATION = 2
"""Item values per location: resting there, or held by someone near it (``V = 2L``)."""

RESTING = slice(0, None, VALUES_PER_LOCATION)
"""On an axis of ``V`` item values, the ``L`` resting ones in location order: a slice, so
``beliefs[..., RESTING]`` is ``(..., L)`` (a view)."""

HELD = slice(1, None, VALUES_PER_LOCATION)
"""On an axis of ``V`` item values, the ``L`` held ones in location order (``(..., L)``)."""


def value_count(locations: int) -> int:
    """``V``: how many values an item has in a scene of ``locations`` item locations (``2L``)."""
    return VALUES_PER_LOCATION * locations


@overload
def value_of(location: int, held: bool = False) -> int: ...
@overload
def value_of(location: IntArray, held: bool | BoolArray = False) -> IntArray: ...
def value_of(location: int | IntArray, held: bool | BoolArray = False) -> int | IntArray:
    """The value of an item resting at location index ``location`` (``held`` false) or held
    by someone near it (true): ``2 l + held``. Elementwise on int64 arrays (``held`` a bool
    or a bool array broadcasting with ``location``)."""
    return VALUES_PER_LOCATION * location + held


@overload
def location_of(value: int) -> int: ...
@overload
def location_of(value: IntArray) -> IntArray: ...
def location_of(value: int | IntArray) -> int | IntArray:
    """The location index of item value(s) ``value`` (``v // 2``), held or not; elementwise
    on int64 arrays (same shape)."""
    return value // VALUES_PER_LOCATION


@overload
def is_held(value: int) -> bool: ...
@overload
def is_held(value: IntArray) -> BoolArray: ...
def is_held(value: int | IntArray) -> bool | BoolArray:
    """Whether item value(s) ``value`` are held by someone (``v`` odd); elementwise on int64
    arrays (a bool array of the same shape)."""
    return value % VALUES_PER_LOCATION == 1


@overload
def is_resting(value: int) -> bool: ...
@overload
def is_resting(value: IntArray) -> BoolArray: ...
def is_resting(value: int | IntArray) -> bool | BoolArray:
    """Whether item value(s) ``value`` rest at their location (``v`` even); elementwise on
    int64 arrays (a bool array of the same shape)."""
    return value % VALUES_PER_LOCATION == 0


@overload
def held_value(value: int) -> int: ...
@overload
def held_value(value: IntArray) -> IntArray: ...
def held_value(value: int | IntArray) -> int | IntArray:
    """The value of the same location as ``value``, held (``v | 1``); elementwise on int64
    arrays (same shape)."""
    return value | 1
