"""The synthetic-ratings study (``studies/rate_synthetic_people.py``) on a tiny case: people who act
by the brain's planner with graded desires on the paper map, raters whose 1-7 ratings are a
noisy monotone function of the generating model's smoothed beliefs at the start and
utilities, then ``toyroom fit --judgments`` comparing graded desires with one favourite.

Four short episodes keep this to seconds; the study's numbers (16 episodes, beta recovered
within 25%, the paired interval of graded minus one favourite) are in docs/fitting.md, from
``python studies/rate_synthetic_people.py``."""

from __future__ import annotations

import csv
from collections import Counter
from pathlib import Path

import pytest
from support import study


@pytest.mark.timeout(120)
def test_graded_people_rated_by_the_generating_model(tmp_path: Path) -> None:
    args = ["--episodes", "4", "--ticks", "300", "--raters", "3", "--grid", "2,4", "--folds", "2"]
    numbers = study("rate_synthetic_people").main([*args, "--workers", "1", "--out", str(tmp_path)])
    with (tmp_path / "ratings.csv").open(newline="") as handle:
        rows = list(csv.DictReader(handle))
    assert rows and set(rows[0]) == {
        "episode",
        "tick",
        "person",
        "quantity",
        "target",
        "value",
        "estimate",
        "participant",
        "question",
    }, f"a rating page's columns, got {list(rows[0]) if rows else 'no rows'}"
    assert {r["value"] for r in rows} <= {str(v) for v in range(1, 8)}, "ratings on a 1-7 scale"
    per_question = Counter((r["episode"], r["question"]) for r in rows)
    assert set(per_question.values()) == {3}, f"every question rated by the 3 raters: {per_question}"
    assert {r["quantity"] for r in rows} == {"belief", "utility"} and {r["estimate"] for r in rows} == {
        "smoothed"
    }
    graded, favourite = numbers["graded-desires"], numbers["one-favourite"]
    assert set(graded["r"]) == {"smoothed belief", "smoothed utility"}, graded["r"]
    assert graded["r"]["smoothed belief"]["mean"] > 0.9, f"beliefs at the start: {graded['r']}"
    assert graded["recovered_likelihood"], f"beta 4 from the decisions, got {graded['beta_likelihood']}"
    difference = numbers["graded-desires_minus_one-favourite"]["smoothed utility"]
    assert difference["lo"] > 0, (
        f"graded desires should agree better with ratings of graded people's utilities: {difference} "
        f"(graded {graded['r']['smoothed utility']}, one favourite {favourite['r']['smoothed utility']})"
    )
    diagnosis = study("diagnose_ratings").main([str(tmp_path)])
    for model in ("graded", "favourite"):
        rows = diagnosis[model]
        assert 0.0 <= rows["favourite found"] <= 1.0 and rows["rating ~ utility"] > 0.5, f"{model}: {rows}"
    favourite = diagnosis["favourite"]
    assert abs(favourite["rating ~ utility"] - favourite["rating ~ P(most wanted)"]) < 1e-9, (
        "one favourite's utility is its P(most wanted)"
    )
