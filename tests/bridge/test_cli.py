"""The `toyroom` command line."""

from __future__ import annotations

import subprocess
import sys


def test_doctor_passes_on_this_install(world: str) -> None:
    result = subprocess.run(
        [sys.executable, "-m", "bridge", "doctor", "--world", world],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert result.returncode == 0, f"doctor failed:\n{result.stdout}\n{result.stderr}"
    assert "all checks passed" in result.stdout
    for tag in ("state", "engine_info", "robot_command", "mind"):
        assert tag in result.stdout


def test_bad_world_name_is_a_clear_error() -> None:
    result = subprocess.run(
        [sys.executable, "-m", "bridge", "doctor", "--world", "no/slashes"],
        capture_output=True,
        text=True,
        timeout=60,
    )
    assert result.returncode == 2 and "world name must be" in result.stderr, result.stderr
