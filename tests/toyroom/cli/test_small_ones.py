"""Small things a newcomer meets: an unknown scenario names the known ones, ``--out`` naming a
file is one clear line, and a passing test session leaves no temporary folders behind."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]


def toyroom(*args: str | Path, timeout: float = 120) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "toyroom", *map(str, args)], capture_output=True, text=True, timeout=timeout
    )


def test_an_unknown_scenario_lists_the_known_ones() -> None:
    result = toyroom("sim", "--scenario", "nosuch")
    assert result.returncode == 2, result.stderr
    assert "scenario 'nosuch': not bundled; known: " in result.stderr, result.stderr
    for name in ("paper-1", "paper-robot", "sally-anne"):
        assert name in result.stderr, f"'{name}' is not among the names offered:\n{result.stderr}"


@pytest.mark.parametrize(
    "command",
    [
        ("run", "--scenario", "paper-1", "--no-live"),
        ("infer", "recording.mcap"),
        ("eval", "--episodes", "1"),
        ("bench", "--quick"),
    ],
    ids=lambda c: c[0],
)
@pytest.mark.parametrize("below", [False, True], ids=["the file", "below a file"])
def test_out_naming_a_file_is_one_clear_line(tmp_path: Path, command: tuple[str, ...], below: bool) -> None:
    afile = tmp_path / "results"
    afile.write_text("not a folder\n")
    out = afile / "sub" if below else afile
    result = toyroom(*command, "--out", out)
    assert result.returncode == 2, f"exit {result.returncode}:\n{result.stdout}\n{result.stderr}"
    assert result.stderr.strip().splitlines() == [
        f"toyroom {command[0]}: --out {out}: expected a folder, got a file"
        + (f" ({afile} is a file)" if below else "")
    ], result.stderr
    assert afile.read_text() == "not a folder\n" and sorted(tmp_path.iterdir()) == [afile]


PASSING = """
def test_writes_into_its_folders(tmp_path, tmp_path_factory):
    (tmp_path / "big.bin").write_bytes(bytes(1_000_000))
    (tmp_path_factory.mktemp("recordings") / "run.mcap").write_bytes(bytes(1_000_000))
"""


def test_a_passing_session_leaves_no_temporary_folders(tmp_path: Path) -> None:
    (tmp_path / "test_inner.py").write_text(PASSING)
    temproot = tmp_path / "temp"
    temproot.mkdir()
    env = {**os.environ, "PYTEST_DEBUG_TEMPROOT": str(temproot)}
    result = subprocess.run(
        [
            sys.executable,
            "-m",
            "pytest",
            "-c",
            str(ROOT / "pyproject.toml"),
            "--rootdir",
            str(ROOT),
            "-p",
            "no:cacheprovider",
            "-q",
            str(tmp_path / "test_inner.py"),
        ],
        capture_output=True,
        text=True,
        timeout=120,
        env=env,
        cwd=tmp_path,
    )
    assert result.returncode == 0, result.stdout + result.stderr
    left = [p for p in temproot.rglob("*") if p.is_file()]
    assert left == [], f"a passing session left {len(left)} files behind: {left[:5]}"
