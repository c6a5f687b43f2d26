"""The optimiser's bounds (pure): every fittable parameter has a range inside what the
settings allow, coordinates map back and forth, and bad ``--bounds`` are named."""

from __future__ import annotations

import pytest

from brain.errors import SettingsError
from brain.settings import ModelSettings
from toyroom.fitting.grid import GRIDS, parse_grid
from toyroom.fitting.optimise import BOUNDS, Bound, parse_bounds, refinement_lines


def test_every_fittable_parameter_has_bounds_the_settings_allow() -> None:
    assert set(BOUNDS) == set(GRIDS)
    for name, bound in BOUNDS.items():
        assert bound.low < bound.high, name
        for value in (bound.low, bound.high):
            ModelSettings(**{name: value})  # type: ignore[arg-type]
        assert not bound.log or bound.low > 0, f"{name}: a log scale needs a positive floor"


@pytest.mark.parametrize("bound", [Bound(1e-3, 0.9), Bound(0.0, 10.0, log=False)])
def test_coordinates_map_back_and_forth(bound: Bound) -> None:
    for u in (0.0, 0.25, 0.5, 1.0):
        assert bound.to_unit(bound.from_unit(u)) == pytest.approx(u, abs=1e-12)
    assert bound.from_unit(-1.0) == bound.low and bound.from_unit(2.0) == pytest.approx(bound.high)
    assert bound.to_unit(bound.low / 10 if bound.log else bound.low - 1) == 0.0, "clipped into the range"


def test_a_log_scale_step_is_a_factor() -> None:
    miss = Bound(1e-3, 0.9)
    step = miss.to_unit(0.3) - miss.to_unit(0.2)
    assert miss.to_unit(0.03) - miss.to_unit(0.02) == pytest.approx(step)


def test_bounds_overrides_are_checked() -> None:
    assert parse_bounds(["miss"], ["miss=0.01,0.5"])["miss"] == Bound(0.01, 0.5)
    for bad, words in [
        ("miss=0.5,0.1", "LO < HI"),
        ("miss=0,0.5", "LO > 0"),
        ("hazard=0.01,0.1", "NAME one of miss"),
        ("miss=a,b", "numbers"),
        ("miss=0.1,1.5", "miss=1.5"),
    ]:
        with pytest.raises(SettingsError, match=words):
            parse_bounds(["miss"], [bad])


def test_the_report_section_gives_both_points_and_the_count() -> None:
    lines = refinement_lines(
        {
            "model": "graded",
            "method": "powell",
            "start": {"miss": 0.2},
            "start_log_likelihood": -100.0,
            "point": {"miss": 0.1234},
            "log_likelihood": -98.5,
            "actions": 50,
            "evaluations": 17,
            "converged": True,
            "message": "Optimization terminated successfully.",
            "seconds": 3.0,
            "bounds": {"miss": [0.001, 0.5]},
        }
    )
    text = "\n".join(lines)
    assert "| grid | miss=0.2 | -100.000 |" in text and "| optimiser | miss=0.1234 | -98.500 |" in text
    assert "17 points evaluated" in text and "converged: yes" in text


def test_a_former_name_fits_the_renamed_parameter() -> None:
    grid = parse_grid("beta,forget", ["forget=0,0.01"])
    assert grid == {"beta": GRIDS["beta"], "forget_per_s": (0.0, 0.01)}, (
        f"expected forget read as forget_per_s, got {grid}"
    )
    bounds = parse_bounds(["forget_per_s"], ["forget=0.001,0.01"])
    assert bounds["forget_per_s"] == Bound(0.001, 0.01), f"expected Bound(0.001, 0.01), got {bounds}"
