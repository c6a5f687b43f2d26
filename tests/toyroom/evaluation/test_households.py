"""``toyroom eval --days N``: households lived over days, each chain of runs with a memory file
of its own, scored per day against a brain without memory; and a brain killed in the middle of
a day, run again, leaves the next day's numbers as they were."""

from __future__ import annotations

import json
import subprocess
import sys
import threading
import time
from pathlib import Path
from typing import Any

import psutil
import pytest
from support import study

DAYS = ["--episodes", "1", "--seed", "3", "--kind", "tasks", "--max-ticks", "250", "--workers", "2"]


def _eval(folder: Path, *extra: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "toyroom", "eval", *DAYS, *extra, "--out", str(folder)],
        capture_output=True,
        text=True,
        timeout=600,
    )


def _days(folder: Path) -> list[dict[str, Any]]:
    (records,) = json.loads((folder / "episodes.json").read_text()).values()
    return records


@pytest.mark.sweep  # three days of four chains end to end: a minute on a quiet machine (make test's budget)
@pytest.mark.timeout(600)
def test_a_household_of_three_days_is_scored_by_day(tmp_path: Path) -> None:
    out = tmp_path / "eval"
    result = _eval(out, "--days", "3", "--policies", "tom")
    assert result.returncode == 0, result.stderr[-3000:]
    records = _days(out)
    assert [r["day"] for r in records] == [1, 2, 3], [r.get("day") for r in records]
    expected = {"btom", "truebelief", "perceptonly", "motion", "btom-fresh", "robot-tom", "robot-tom-fresh"}
    for record in records:
        assert expected <= set(record), f"day {record['day']}: runs {sorted(record)}"
        assert "error" not in record, record.get("error")
    (condition,) = json.loads((out / "metrics.json").read_text())["conditions"]
    assert sorted(condition["by_day"]) == ["1", "2", "3"] and "later" in condition, sorted(condition)
    day2 = condition["by_day"]["2"]
    assert set(day2["robot"]) == {"tom", "tom-fresh", "none"}, sorted(day2["robot"])
    report = (out / "report.md").read_text()
    assert "| day |" in report and "| 3+ |" in report and "detection btom-fresh" in report, report[:2000]
    assert (out / "days-omniscient-simple-tasks.png").stat().st_size > 5000
    memory = next(out.glob("work/*/household-0/memory/observe.sqlite"))
    shown = subprocess.run(
        [sys.executable, "-m", "toyroom", "memory", "show", str(memory)],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert shown.returncode == 0 and "gen-" in shown.stdout, shown.stdout + shown.stderr
    for day in ("1", "2", "3"):
        assert f"│ {day}   " in shown.stdout, f"day {day}'s end is not remembered:\n{shown.stdout}"
    second = next(out.glob("work/*/household-0/scenarios/observe/*-d2.toml")).read_text()
    assert "[household]" in second and "day = 2" in second, second[-400:]
    desires = study("household_desires").rows(out)  # the study that reads such a folder
    assert all(1 <= r[0] <= 3 and all(0.0 <= v <= 1.0 for v in r[2:]) for r in desires), desires


def _connected(process: psutil.Process) -> bool:
    """Whether ``process`` holds an established TCP connection (its Zenoh session is open)."""
    try:
        return any(c.status == psutil.CONN_ESTABLISHED for c in process.net_connections("tcp"))
    except (psutil.NoSuchProcess, psutil.AccessDenied):
        return False


def _kill_on_day_three(stop: threading.Event, killed: list[int]) -> None:
    """SIGKILL the first brain of day 3 of the chain with memory once its Zenoh session is
    connected, so mid-day. A kill timed from when the brain was first seen (a second, then a
    fifth of one) missed on a loaded machine: CI at a32918b found no day-3 brain to kill, and
    CI at d1eeb9f killed one whose day had already been scored."""
    while not stop.is_set() and not killed:
        for process in psutil.process_iter(["pid", "cmdline"]):
            command = " ".join(process.info["cmdline"] or [])
            if "-m brain" in command and "-d3.toml" in command and "observe.sqlite" in command:
                while not stop.is_set() and process.is_running() and not _connected(process):
                    time.sleep(0.01)
                try:
                    process.kill()
                    killed.append(process.info["pid"])
                except psutil.NoSuchProcess:
                    pass
                break
        time.sleep(0.05)


@pytest.mark.sweep  # four days with a kill: a minute and a half, beyond make test's budget
@pytest.mark.timeout(900)
def test_a_brain_killed_on_day_three_leaves_day_four_as_it_was(tmp_path: Path) -> None:
    """A process pair a run (``--batch 1``: the brain's command line names its day); a serving
    brain killed mid-day: test_households_batch.py."""
    whole = _eval(tmp_path / "whole", "--days", "4", "--policies", "none", "--batch", "1")
    assert whole.returncode == 0, whole.stderr[-3000:]
    stop, killed = threading.Event(), []
    watcher = threading.Thread(target=_kill_on_day_three, args=(stop, killed), daemon=True)
    watcher.start()
    try:
        broken = _eval(tmp_path / "broken", "--days", "4", "--policies", "none", "--batch", "1")
    finally:
        stop.set()
        watcher.join(timeout=10)
    assert killed, "no brain of day 3 was found to kill"
    assert broken.returncode == 0, broken.stderr[-3000:]
    before, after = _days(tmp_path / "whole"), _days(tmp_path / "broken")
    assert after[2].get("failed_runs"), f"day 3's killed run is not on record: {after[2]}"
    scored = ("btom", "btom-fresh", "perceptonly", "truebelief", "motion")
    for day in (4,):
        for key in scored:
            assert after[day - 1][key] == before[day - 1][key], f"day {day}, {key}: the kill changed it"
