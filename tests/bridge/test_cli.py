"""The `toyroom` command line."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from bridge.doctor import run_doctor
from protocol.schema import write_schemas


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


def test_doctor_warns_on_stale_schemas_without_failing(world: str, tmp_path: Path, capsys) -> None:
    write_schemas(tmp_path)
    state = tmp_path / "state.json"
    state.write_text(state.read_text().replace('"minimum": 0', '"minimum": 1'))
    code = run_doctor(world, repeats=2, schema_dir=tmp_path)
    printed = capsys.readouterr().out
    assert code == 0, f"doctor failed on stale schemas alone (expected a warning):\n{printed}"
    assert "warning" in printed and "state.json" in printed, printed
