"""The parameters ``toyroom fit`` searches, and their grids (pure).

Each fittable parameter is a :class:`~brain.settings.ModelSettings` field with a default
grid around its default value; ``--grid NAME=V1,V2,...`` replaces one. A point of the
search is one value per parameter (the cartesian product of the grids).
"""

from __future__ import annotations

import dataclasses
import itertools
from collections.abc import Mapping, Sequence

from brain.errors import SettingsError
from brain.settings import ModelSettings, current_name

GRIDS: dict[str, tuple[float, ...]] = {
    "beta": (0.5, 1.0, 2.0, 4.0),
    "hazard": (0.001, 0.01, 0.05),
    "epsilon": (0.001, 0.01, 0.05),
    "r": (1.0, 8.0, 64.0),
    "delta": (0.0, 0.01, 0.05),
    "ignorance": (0.1, 0.5, 0.9),
    "step_cost": (0.1, 1.0, 3.0),
    "miss": (0.0, 0.1, 0.3),
    "hearsay_per_s": (0.0, 0.1, 0.3),
    "forget_per_s": (0.0, 0.003, 0.01),
}
"""The default grid of each parameter ``toyroom fit --params`` may name."""

Point = dict[str, float]
"""One value per fitted parameter."""


def parse_grid(params: str, overrides: Sequence[str] = ()) -> dict[str, tuple[float, ...]]:
    """The grid of each parameter named in ``params`` (comma-separated), with ``NAME=V1,V2``
    overrides.

    Raises:
        SettingsError: naming a parameter that cannot be fitted or a value that is not a
            number, or an override of a parameter not in ``params``.
    """
    names = [current_name(n.strip()) for n in params.split(",") if n.strip()]
    unknown = [n for n in names if n not in GRIDS]
    if unknown or not names:
        raise SettingsError(
            f"cannot fit {', '.join(map(repr, unknown)) or 'nothing'}; fittable: {', '.join(GRIDS)}"
        )
    grid = {n: GRIDS[n] for n in names}
    for text in overrides:
        name, sep, values = text.partition("=")
        name = current_name(name.strip())
        if not sep or name not in grid:
            raise SettingsError(
                f"--grid {text!r}: expected NAME=V1,V2,... with NAME one of {', '.join(grid)}"
            )
        try:
            grid[name] = tuple(float(v) for v in values.split(",") if v.strip())
        except ValueError:
            raise SettingsError(f"--grid {text!r}: the values must be numbers") from None
        if not grid[name]:
            raise SettingsError(f"--grid {text!r}: no values")
    return grid


def points(grid: Mapping[str, Sequence[float]]) -> list[Point]:
    """Every point of the grid (the first parameter varies slowest)."""
    names = list(grid)
    return [dict(zip(names, values, strict=True)) for values in itertools.product(*grid.values())]


def apply(settings: ModelSettings, point: Mapping[str, float]) -> ModelSettings:
    """``settings`` with the point's values.

    Raises:
        SettingsError: when a value is out of its range (the settings' own check)."""
    try:
        return dataclasses.replace(settings, **dict(point))  # type: ignore[arg-type]
    except ValueError as err:
        raise SettingsError(str(err)) from None
