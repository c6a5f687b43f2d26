"""``python -m sim2d export`` (``toyroom export-scenario``): a scenario as one JSON document
for engines that cannot read TOML."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import msgspec

from protocol import Scene
from sim2d.engine import Engine
from sim2d.export import FORMAT, export


def test_the_export_carries_the_engines_own_scene_and_the_scripts() -> None:
    data = json.loads(msgspec.json.encode(export("paper-2")))
    assert data["format"] == FORMAT and data["name"] == "paper-2" and data["robot"] == "observe"
    assert msgspec.convert(data["scene"], Scene) == Engine("paper-2", check_policy=False).scene()
    a1 = next(a for a in data["agents"] if a["id"] == "A1")
    assert a1["script"][0] == {"do": "play", "ticks": 20, "label": "0"}, a1["script"][0]
    assert a1["home"] == {"col": a1["home"]["col"], "row": a1["home"]["row"]} and a1["wants"] == "skate"
    assert {i["id"]: i["at"] for i in data["items"]} == {"skate": "A1", "ball": "A2"}


def test_the_command_writes_a_file_and_names_a_broken_scenario(tmp_path: Path) -> None:
    out = tmp_path / "paper-1.json"
    command = [sys.executable, "-m", "toyroom", "export-scenario", "--scenario", "paper-1", "--out", str(out)]
    assert subprocess.run(command, capture_output=True, text=True, timeout=60).returncode == 0
    assert json.loads(out.read_text())["name"] == "paper-1"
    broken = tmp_path / "broken.toml"
    broken.write_text('name = "broken"\nmap = "nowhere"\n')
    command[command.index("paper-1")] = str(broken)
    result = subprocess.run(command, capture_output=True, text=True, timeout=60)
    assert result.returncode == 2 and "nowhere.map.toml" in result.stderr, result.stderr
