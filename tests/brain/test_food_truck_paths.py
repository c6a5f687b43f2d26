"""Desires as people read them (issue 54) on the food trucks' path types
(``examples/food-trucks/``): after each clip, the student's smoothed expected utility of
each truck on the study's 1-7 scale and P(most wanted) order the trucks the way people do,
for one favourite and for graded desires, on sim2d in one process and on the grid engine
over the wire."""

from __future__ import annotations

import csv
import dataclasses
import itertools
from pathlib import Path

import numpy as np
import pytest
from support import study, toyroom_run

from brain.model.desires import on_scale
from brain.settings import ModelSettings

SCENES = Path(__file__).resolve().parents[2] / "examples" / "food-trucks"
TRUCKS = ("korean", "lebanese", "mexican")
PATTERNS = {
    "check-and-go-back": "Mexican > Korean > Lebanese",
    "check-and-go-back-empty": "Lebanese = Mexican > Korean",
    "check-and-stay": "Lebanese > Mexican > Korean",
    "no-check": "Korean > Lebanese = Mexican",
    "no-check-empty": "Korean > Lebanese = Mexican",
    "cut-short": "Mexican > Lebanese > Korean",
    "cut-short-empty": "Lebanese = Mexican > Korean",
}
"""The ordering people give after each clip (``examples/food-trucks/README.md`` says where
each comes from): ``>`` more wanted, ``=`` alike."""
TIE = 1e-6


def mismatch(pattern: str, values: dict[str, float]) -> str | None:
    """Why ``values`` (by truck) break ``pattern``, or ``None`` when they follow it."""
    groups = [[name.strip().lower() for name in group.split("=")] for group in pattern.split(">")]
    for group in groups:
        spread = max(values[t] for t in group) - min(values[t] for t in group)
        if spread > TIE:
            return f"{' = '.join(group)} differ by {spread:.3g}"
    for above, below in itertools.pairwise(groups):
        if min(values[t] for t in above) <= max(values[t] for t in below) + TIE:
            return f"{'/'.join(above)} not above {'/'.join(below)}"
    return None


def read(
    path: str, settings: ModelSettings, on_arrival: bool = False
) -> tuple[dict[str, float], dict[str, float]]:
    """The student's smoothed ``(E[u] on 1-7, P(most wanted))`` by truck after the clip
    (``on_arrival``: after the first tick in the gap), as ``studies/food_truck_paths.py``
    reads it."""
    paths = study("food_truck_paths")
    reading = paths.read(path, settings, on_arrival)
    scale, most = (dict(zip(paths.TRUCKS, map(float, v), strict=True)) for v in (reading.scale, reading.most))
    return scale, most


MODELS = {"favourite": ModelSettings(), "graded": dataclasses.replace(ModelSettings(), desire_model="graded")}


@pytest.mark.parametrize("model", list(MODELS))
@pytest.mark.parametrize("path", list(PATTERNS))
def test_the_trucks_are_ordered_as_people_order_them(path: str, model: str) -> None:
    utility, most = read(path, MODELS[model])
    for name, values in (("E[u] on 1-7", utility), ("P(most wanted)", most)):
        why = mismatch(PATTERNS[path], values)
        assert why is None, (
            f"{path}, {model} desires: expected {PATTERNS[path]} by {name}, got "
            + ", ".join(f"{t} {v:.3f}" for t, v in values.items())
            + f" ({why})"
        )


def test_each_scene_states_the_ordering_it_is_tested_against() -> None:
    for path, pattern in PATTERNS.items():
        assert f"The reading expected (README.md): {pattern}." in (SCENES / f"{path}.toml").read_text(), (
            f"{path}.toml: expected its comment to state '{pattern}'"
        )


@pytest.mark.parametrize("model", list(MODELS))
def test_a_clip_cut_on_arrival_cannot_tell_the_far_trucks_apart(model: str) -> None:
    """At the tick the far spot comes into view no decision has been made in view of it, and
    everything before is the same with the Lebanese and the Mexican truck swapped: exactly
    alike. The Mexican truck comes first only from what the student does (or does not do)
    once the Lebanese one is in view: here, stop for 1 s instead of heading for it."""
    utility, most = read("cut-short", MODELS[model], on_arrival=True)
    assert abs(utility["lebanese"] - utility["mexican"]) < TIE, utility
    assert abs(most["lebanese"] - most["mexican"]) < TIE, most
    after, _ = read("cut-short", MODELS[model])
    assert after["mexican"] > after["lebanese"] + 0.5, after


def final_desires(out: Path) -> tuple[dict[str, float], dict[str, float]]:
    """The student's smoothed expected utility (1-7, the default's goal scale) and P(most
    wanted) by truck at the last tick of a run's ``mind.csv``."""
    with (out / "mind.csv").open(newline="") as handle:
        rows = [r for r in csv.DictReader(handle) if r["agent"] == "student"]
    last = max(int(r["tick"]) for r in rows)
    end = [r for r in rows if int(r["tick"]) == last]
    u = {
        r["item"]: float(r["p_smoothed"])
        for r in end
        if r["quantity"] == "desire" and r["value"] == "utility"
    }
    settings = ModelSettings()
    scale = on_scale(np.array([u[t] for t in (*TRUCKS, "out")]), settings)
    most = {r["item"]: float(r["p_smoothed"]) for r in end if r["quantity"] == "preference"}
    return {t: float(scale[i]) for i, t in enumerate(TRUCKS)}, {t: most[t] for t in TRUCKS}


@pytest.mark.parametrize("path", ["check-and-go-back", "check-and-stay", "cut-short"])
def test_the_orderings_hold_on_the_grid_engine(tmp_path: Path, path: str) -> None:
    """The three path types of issue 54's "Done when" through the protocol: the grid engine
    and the brain as processes, read from ``mind.csv``."""
    out = toyroom_run(
        tmp_path, str(SCENES / f"{path}.toml"), "--robot", "observe", "--no-live", "--engine", "grid"
    )
    utility, most = final_desires(out)
    for name, values in (("E[u] on 1-7", utility), ("P(most wanted)", most)):
        why = mismatch(PATTERNS[path], values)
        assert why is None, (
            f"{path} on the grid engine: expected {PATTERNS[path]} by {name}, got {values} ({why})"
        )
