"""Recordings of real runs (engine and brain over loopback Zenoh) shared by the fit tests."""

from __future__ import annotations

from pathlib import Path

import pytest
from support import toyroom_run

SCENARIOS = ("sally-anne", "paper-1", "paper-2")


@pytest.fixture(scope="session")
def recordings(tmp_path_factory: pytest.TempPathFactory) -> list[Path]:
    """``trace.jsonl`` of each of :data:`SCENARIOS`, the robot observing."""
    root = tmp_path_factory.mktemp("recordings")
    return [toyroom_run(root / s, s, "--no-live", "--robot", "observe") / "trace.jsonl" for s in SCENARIOS]
