"""The benchmark scripts run (their numbers are for people; no timing is asserted here)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def test_brain_bench_runs() -> None:
    result = subprocess.run(
        [sys.executable, str(ROOT / "bench" / "brain_bench.py"), "--repeats", "1"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert result.returncode == 0, result.stderr
    assert "planner, cold (s)" in result.stdout and "online step per person" in result.stdout


def test_view_bench_runs() -> None:
    result = subprocess.run(
        [sys.executable, str(ROOT / "bench" / "view_bench.py")], capture_output=True, text=True, timeout=300
    )
    assert result.returncode == 0, result.stderr
    assert "frame, median" in result.stdout
