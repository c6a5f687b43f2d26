"""``toyroom bench`` and its measurements run (their numbers are for people; no timing is
asserted here)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

pytestmark = pytest.mark.sweep  # a benchmark or study run end to end: `make sweeps` (tests/tiers.py)


def test_the_brain_step_measurement_runs_alone() -> None:
    result = subprocess.run(
        [sys.executable, "-m", "toyroom.bench.brainstep", "--repeats", "1"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert result.returncode == 0, result.stderr
    assert "planner, cold (s)" in result.stdout and "online step per person" in result.stdout
    assert "graded" in result.stdout, "the graded belief model should be measured beside the point one"


def test_toyroom_bench_quick_writes_its_numbers(tmp_path: Path) -> None:
    import json

    result = subprocess.run(
        [sys.executable, "-m", "toyroom", "bench", "--quick", "--out", str(tmp_path)],
        capture_output=True,
        text=True,
        timeout=420,  # (the households' embodied row: about 30 s of it on a loaded 2-core machine)
    )
    assert result.returncode == 0, result.stderr
    numbers = json.loads((tmp_path / "bench.json").read_text())
    for field in (
        "zenoh_rtt_us",
        "bridge_rtt_us",
        "lockstep_tick_us",
        "lockstep_ticks_per_s",
        "brain_step_us",
        "planner_cold_s",
        "scaling",
        "gateway",
        "eval_seconds_per_episode",
    ):
        assert field in numbers, field
    assert numbers["zenoh_rtt_us"] > 0 and numbers["lockstep_ticks_per_s"] > 0
    ticks = numbers["gateway"]["lockstep_tick_us"]
    assert ticks["direct"] > 0 and ticks["gateway"] > 0 and ticks["csharp"] > 0, ticks
    assert numbers["eval_seconds_per_episode"] > 0 and numbers["eval_timing"]["episodes"] == 2
    assert numbers["graded"]["brain_step_us"]["median"] > 0 and numbers["graded"]["planner_cold_s"] > 0
    rows = numbers["scaling"]
    for row in rows:
        for field in (
            "rooms",
            "items",
            "people",
            "worlds",
            "step_us",
            "tick_us",
            "first_order_tick_us",
            "nested_pairs",
            "smoothed",
            "memory_per_person_bytes",
            "planner_s",
            "exact",
            "tv_vs_exact",
        ):
            assert field in row, f"scaling rows need '{field}', got {sorted(row)}"
    assert max(r["people"] for r in rows) == 8, "the family should reach households of eight"
    small = rows[0]["smoothed"]
    assert 0 <= small["tv_vs_exact"] <= 0.05 and small["seconds"] > 0, small
    profile = numbers["lockstep_profile"]
    mixed = profile["interleaved"]
    assert profile["zenoh_query_two_processes_us"] > 0 < profile["typed_query_us"], profile
    assert 0 < mixed["ratio_lo"] <= mixed["ratio"] <= mixed["ratio_hi"], f"the tick's ratio range: {mixed}"
    assert mixed["typed_query_ratio_lo"] <= mixed["typed_query_ratio"] <= mixed["typed_query_ratio_hi"], mixed
    assert all(cpu > 0 for cpu in mixed["cpu_us_per_round_trip"].values()), mixed["cpu_us_per_round_trip"]
    against = numbers["lockstep_profile"]["engine_step_vs_review"]
    assert against is None or against["now_us"] > 0 < against["then_us"], against
    sizes = [(r["rooms"], r["items"]) for r in rows]
    assert sizes[0] == (4, 2) and max(sizes) >= (10, 6), (
        f"the family should span 4r/2i to 10r/6i, got {sizes}"
    )
    assert all(r["tv_vs_exact"] is not None for r in rows if r["worlds"] <= 1000), (
        f"tv_vs_exact is due wherever the exact model fits: {rows}"
    )
    big = [r for r in rows if r["worlds"] > 10**6]
    assert big and not any(r["exact"] for r in big), f"large houses should run factored: {big}"
    assert (tmp_path / "perf.md").exists() and (tmp_path / "scaling.png").stat().st_size > 0
    row = numbers["households_embodied"]  # issue 66: the largest household, embodied, lapses on
    assert (row["rooms"], row["items"], row["people"], row["miss"]) == (20, 10, 8, 0.2), row
    for robot in ("embodied", "omniscient"):
        for field in ("peak_gib", "first_look_s", "tick_ms", "tick_p99_ms"):
            assert row[robot][field] > 0, (robot, field, row[robot])
    assert row["embodied"]["rows"] > 1 == row["omniscient"]["rows"], "only the embodied robot keeps rows"
    printed = result.stdout
    assert "households embodied row" in printed and "tick ms, p99" in printed, printed[-3000:]
    assert "Households with a robot that sees only" in (tmp_path / "perf.md").read_text()


def test_the_memory_measurement_reads_a_brains_peak(tmp_path: Path) -> None:
    """One of ``toyroom bench --memory``'s runs (house-a, seed 2, miss 0.2, embodied): it ends,
    and its peak is a brain's (more than the 100 MB any brain starts with), within the budget."""
    from brain.model.size import MEMORY_BUDGET_GB
    from toyroom.bench.memory import measure

    run = measure("house-a", 2, tmp_path)
    assert run.code == 0, f"the run failed: {run.message}"
    assert 0.1 < run.peak_gb <= MEMORY_BUDGET_GB, f"peak {run.peak_gb:.2f} GiB"
