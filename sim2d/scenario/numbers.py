"""Numbers of scenario and map files, read strictly: an integer field takes an integer
(``columns = 5.9`` is an error, not 5; ``true`` is no number), a real field a finite number
in its range (``cell_size = nan`` or ``inf`` is an error here, not an invalid
``engine_info`` later). Each error is one line naming the file, the key and the value."""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

from ..errors import ScenarioError


def integer(value: Any, path: Path, entry: str, key: str, low: int = 1, high: int | None = None) -> int:
    """``value``, an integer from ``low`` to ``high`` (no bound when ``None``).

    Raises:
        ScenarioError: ``key`` is no integer (a float, a string, a boolean) or out of range.
    """
    if not isinstance(value, int) or isinstance(value, bool):
        raise ScenarioError(path, entry, f"{key} must be an integer, got {value!r}")
    if value < low or (high is not None and value > high):
        bound = f"from {low:,} to {high:,}" if high is not None else f"at least {low:,}"
        raise ScenarioError(path, entry, f"{key} must be an integer {bound}, got {value:,}")
    return value


def real(
    value: Any, path: Path, entry: str, key: str, high: float, low: float | None = None, why: str = ""
) -> float:
    """``value``, a finite number above 0 (from ``low``, when given) and at most ``high`` (an
    integer will do); ``why``: the reason for ``low``, which its error gives.

    Raises:
        ScenarioError: ``key`` is no number, NaN, infinite, at most 0, below ``low`` or above ``high``.
    """
    if not isinstance(value, int | float) or isinstance(value, bool):
        raise ScenarioError(path, entry, f"{key} must be a number, got {value!r}")
    if not (math.isfinite(value) and 0 < value <= high and (low is None or value >= low)):
        bound = "above 0" if low is None else f"from {low:g}"
        reason = f" ({why})" if why and low is not None else ""
        raise ScenarioError(
            path, entry, f"{key} must be a finite number {bound} and at most {high:g}{reason}, got {value!r}"
        )
    return float(value)
