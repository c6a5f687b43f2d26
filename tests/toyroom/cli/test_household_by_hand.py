"""A household lived by hand (docs/usage.md): the doc's shell block run as written, three days
of ``toyroom generate --day``, ``toyroom run --memory`` and ``toyroom morning``; and the
morning command's refusals (one line, exit 2). Real processes and files."""

from __future__ import annotations

import json
import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]
SECTION = "### A household lived by hand"


def _block() -> str:
    """The ``sh`` block of the section, as the docs show it."""
    text = (ROOT / "docs" / "usage.md").read_text(encoding="utf-8")
    assert SECTION in text, f"docs/usage.md has no section {SECTION!r}"
    section = text[text.index(SECTION) :]
    start = section.index("```sh\n") + len("```sh\n")
    return section[start : section.index("```", start)]


def _shell(script: str, cwd: Path) -> subprocess.CompletedProcess[str]:
    env = {**os.environ, "PATH": f"{Path(sys.executable).parent}{os.pathsep}{os.environ['PATH']}"}
    return subprocess.run(
        ["bash", "-e", "-c", script], cwd=cwd, env=env, capture_output=True, text=True, timeout=300
    )


def _morning(*args: str | Path) -> subprocess.CompletedProcess[str]:
    command = [sys.executable, "-m", "toyroom", "morning", *map(str, args)]
    return subprocess.run(command, capture_output=True, text=True, timeout=120)


@pytest.mark.timeout(400)
def test_three_days_by_hand_run_as_the_docs_write_them(tmp_path: Path) -> None:
    assert shutil.which("toyroom", path=str(Path(sys.executable).parent)), "no toyroom script beside python"
    result = _shell(_block(), tmp_path)
    assert result.returncode == 0, f"expected exit 0, got {result.returncode}:\n{result.stderr[-3000:]}"
    for day in (1, 2):
        morning = json.loads((tmp_path / "h7" / f"morning{day}.json").read_text())
        named = (morning.get("household"), morning.get("map"))
        assert named == ("gen-paper-s7", "paper"), (
            f"morning {day}: expected its household and map, got {named}"
        )
        assert set(morning["favourites"]) == {"A1", "A2"}, (
            f"morning {day}: people {sorted(morning['favourites'])}"
        )
        wrote = f"wrote h7/morning{day}.json: household 'gen-paper-s7' on paper, day {day}'s end (tick 120)"
        assert wrote in result.stdout, f"expected {wrote!r} in the output, got:\n{result.stdout[-2000:]}"
    third = (tmp_path / "h7" / "gen-paper-s7-d3.toml").read_text()
    assert "day = 3" in third, third[-300:]
    log = (tmp_path / "day3" / "brain.log").read_text()
    assert "household 'gen-paper-s7' day 3: starting from day 2's end" in log, log[-2000:]
    shown = [line for line in result.stdout.splitlines() if "gen-paper-s7" in line and "│" in line]
    assert shown and all("│ 3 " in line for line in shown), f"expected day 3's rows, got {shown}"
    _refuses_other_recordings(tmp_path / "day1" / "trace.jsonl", tmp_path)


def _refuses_other_recordings(trace: Path, folder: Path) -> None:
    """A day's recording with no ``[household]``, and one cut off mid-line, give no morning."""
    lines = trace.read_text().splitlines(keepends=True)
    plain = []
    for line in lines:
        record = json.loads(line)
        if record["payload"].get("type") == "engine_info":
            record["payload"]["scene"].pop("household", None)
        plain.append(json.dumps(record) + "\n")
    (folder / "plain.jsonl").write_text("".join(plain))
    (folder / "cut.jsonl").write_text("".join(lines[: len(lines) // 2]) + lines[len(lines) // 2][:40])
    for name, said in (("plain.jsonl", "names no household"), ("cut.jsonl", "cut off")):
        result = _morning(folder / name)
        got = (result.returncode, len(result.stderr.strip().splitlines()), said in result.stderr)
        assert got == (2, 1, True), f"{name}: expected exit 2, one line with {said!r}, got {result.stderr!r}"


@pytest.mark.timeout(200)
def test_a_morning_is_refused_for_a_run_that_gives_none(tmp_path: Path) -> None:
    unfinished = tmp_path / "stopped"
    unfinished.mkdir()
    (unfinished / "trace.jsonl").write_text("")
    (unfinished / "FAILED").write_text("stopped by SIGINT\n")
    cases = {
        "missing": (tmp_path / "nothing", "no such file"),
        "not a run": (tmp_path, "no trace.jsonl"),
        "unfinished": (unfinished, "did not finish"),
    }
    for name, (run, said) in cases.items():
        result = _morning(run, "--out", tmp_path / "m.json")
        lines = result.stderr.strip().splitlines()
        got = (result.returncode, len(lines), said in result.stderr)
        assert got == (2, 1, True), (
            f"{name}: expected exit 2 and one line with {said!r}, got {result.stderr!r}"
        )
        assert not (tmp_path / "m.json").exists(), f"{name}: a morning was written"
