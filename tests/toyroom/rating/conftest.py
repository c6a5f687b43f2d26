"""Recordings the rating tests stand on: real runs of paper-robot and paper-robot-decline."""

from __future__ import annotations

from pathlib import Path

import pytest
from support import toyroom_run


@pytest.fixture(scope="session")
def recordings(tmp_path_factory: pytest.TempPathFactory) -> list[Path]:
    """Runs of paper-robot and paper-robot-decline, recorded to MCAP (the fit's folds need two)."""
    folder = tmp_path_factory.mktemp("run")
    for name, scenario in (("robot", "paper-robot"), ("decline", "paper-robot-decline")):
        toyroom_run(folder / name, scenario, "--no-live", "--record", str(folder / f"{name}.mcap"))
    return [folder / "robot.mcap", folder / "decline.mcap"]
