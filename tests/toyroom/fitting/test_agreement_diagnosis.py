"""``bench/agreement_diagnosis.py`` on a tiny case: simulated people rated from their true
beliefs and utilities, the observer's configurations read on the same episodes and paired.
The study's numbers (24 episodes) are in docs/fitting.md, "Why graded desires and the
belief-space planner lower agreement"."""

from __future__ import annotations

import importlib.util
import math
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]


def bench() -> object:
    spec = importlib.util.spec_from_file_location(
        "agreement_diagnosis", ROOT / "bench" / "agreement_diagnosis.py"
    )
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = module  # its dataclasses look their module up
    spec.loader.exec_module(module)
    return module


@pytest.mark.timeout(120)
def test_configurations_read_on_the_same_episodes() -> None:
    module = bench()
    configs = "qmdp-graded,belief-graded,qmdp-favourite"
    numbers = module.main(["--episodes", "2", "--ticks", "300", "--raters", "3", "--configs", configs])  # type: ignore[attr-defined]
    ratings = numbers["ratings"]
    assert set(ratings) == {*configs.split(","), "differences"}, list(ratings)
    assert set(ratings["differences"]) == {
        "belief-graded - qmdp-graded",
        "qmdp-favourite - qmdp-graded",
    }, list(ratings["differences"])
    for name in configs.split(","):
        belief = ratings[name]["smoothed belief start"]
        assert belief["mean"] > 0.8, f"{name}: start beliefs from the true beliefs: {belief}"
        assert {"smoothed utility E[u]", "smoothed utility P(top)", "online utility -rank"} <= set(
            ratings[name]
        )
    for times in numbers["calibration"].values():
        assert all(math.isfinite(row["brier"]) for row in times.values()), times


def test_a_configuration_names_a_planner_and_desires() -> None:
    config = bench().Config  # type: ignore[attr-defined]
    assert config.parse("belief-graded-5-unique") == config(
        "belief-graded-5-unique", "belief", "graded", 5, True
    )
    for bad in (
        "graded",
        "qmdp-favourite-unique",
        "qmdp-graded-1",
        "pomdp-graded",
        "qmdp-graded-hazardfirst",
    ):
        with pytest.raises(ValueError):
            config.parse(bad)
