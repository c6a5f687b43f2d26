"""``studies/diagnose_agreement.py`` on a tiny case: simulated people rated from their true
beliefs and utilities, the observer's configurations read on the same episodes and paired.
The study's numbers (24 episodes) are in docs/fitting.md, "Why graded desires and the
belief-space planner lower agreement"."""

from __future__ import annotations

import math

import pytest
from support import study


@pytest.mark.sweep  # a study run end to end: `make sweeps` (tests/tiers.py)
@pytest.mark.timeout(120)
def test_configurations_read_on_the_same_episodes() -> None:
    module = study("diagnose_agreement")
    configs = "qmdp-graded,belief-graded,qmdp-favourite"
    numbers = module.main(["--episodes", "2", "--ticks", "300", "--raters", "3", "--configs", configs])
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
    config = study("diagnose_agreement").Config
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
