"""The array types of the model's math (numpy), named once."""

from __future__ import annotations

import numpy as np
import numpy.typing as npt

FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.int64]
BoolArray = npt.NDArray[np.bool_]

TIE = 1e-12
"""Probabilities closer than this are equal when the likeliest is picked, so that the pick
does not hang on rounding (two sums of the same terms in another order may differ in the
last bit): the first of them wins, as the first of exactly equal ones does."""


def first_max(values: npt.ArrayLike) -> int:
    """The index of the first of ``(N,)`` values within :data:`TIE` of their maximum."""
    array = np.asarray(values, dtype=np.float64)
    return int(np.argmax(array >= array.max() - TIE))
