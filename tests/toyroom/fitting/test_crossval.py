"""Cross-validation and grids of ``toyroom fit`` on hand-made tables."""

from __future__ import annotations

import numpy as np
import pytest

from brain.errors import SettingsError
from toyroom.fitting import cross_validate, folds, held_out_per_action, parse_grid, points


def test_folds_partition_the_episodes() -> None:
    parts = folds(7, 3, seed=1)
    assert len(parts) == 3 and sorted(np.concatenate(parts).tolist()) == list(range(7)), parts
    with pytest.raises(ValueError, match="at least k episodes"):
        folds(2, 3)


def test_each_fold_is_fitted_on_the_others_and_scored_on_itself() -> None:
    """Point 0 explains episodes 0-1 best, point 1 episodes 2-3: fitted without episodes
    0-1, a fold picks point 1 and scores episodes 0-1 there (-3 - 3 = -6 over 4 actions)."""
    ll = np.array([[-1.0, -1.0, -5.0, -5.0], [-3.0, -3.0, -2.0, -2.0]])
    actions = np.array([2, 2, 2, 2])
    result = cross_validate(ll, actions, [np.array([0, 1]), np.array([2, 3])])
    assert [f.best for f in result] == [1, 0], "each fold should pick the point its training episodes favour"
    assert result[0].log_likelihood == -6.0 and result[0].per_action == -1.5, result[0]
    assert result[1].log_likelihood == -10.0, result[1]
    assert held_out_per_action(result) == pytest.approx(-16.0 / 8)


def test_grids_name_what_cannot_be_fitted() -> None:
    grid = parse_grid("beta,hazard", ["beta=1,3"])
    assert grid["beta"] == (1.0, 3.0) and len(points(grid)) == 2 * len(grid["hazard"])
    with pytest.raises(SettingsError, match="'gamma'"):
        parse_grid("beta,gamma")
    with pytest.raises(SettingsError, match="numbers"):
        parse_grid("beta", ["beta=1,x"])
    with pytest.raises(SettingsError, match="NAME one of beta"):
        parse_grid("beta", ["hazard=0.1"])
