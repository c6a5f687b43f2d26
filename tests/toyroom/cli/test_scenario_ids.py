"""A scenario or map whose id no message may carry (a space, a ``*``, an emoji) is refused by
sim2d's loader in one line, exit 2 (issue 64, item 14): ``toyroom export-scenario`` used to
accept it, and ``toyroom run`` started the nodes and then failed at the handshake (exit 1, a
``FAILED`` folder); now the run checks the scenario before any node starts and makes no folder.
Real ``toyroom`` processes."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest

from sim2d.errors import ScenarioError
from sim2d.scenario.scenario import load_scenario

SCENARIOS = Path(__file__).resolve().parents[3] / "sim2d" / "scenarios"
BAD_IDS = ["sk ate", "sk*ate", "sk\N{GRINNING FACE}ate"]


def _with_item_id(folder: Path, item: str) -> Path:
    """paper-1 (its map beside it) with the item ``skate`` renamed ``item``."""
    (folder / "paper.map.toml").write_text((SCENARIOS / "paper.map.toml").read_text())
    text = (SCENARIOS / "paper-1.toml").read_text()
    assert 'id = "skate"' in text, "paper-1's items changed: update this test"
    path = folder / "bad-id.toml"
    path.write_text(text.replace('"skate"', f'"{item}"'), encoding="utf-8")
    return path


def _toyroom(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "toyroom", *args], capture_output=True, text=True, timeout=120
    )


@pytest.mark.parametrize("item", BAD_IDS, ids=ascii)
def test_export_and_run_refuse_an_id_no_message_may_carry(tmp_path: Path, item: str) -> None:
    scenario = _with_item_id(tmp_path, item)
    said = f"items[0]: id {item!r} is not an id: expected a letter, then up to 63 letters, digits"
    exported = _toyroom("export-scenario", "--scenario", str(scenario), "--out", str(tmp_path / "s.json"))
    lines = exported.stderr.strip().splitlines()
    assert exported.returncode == 2 and len(lines) == 1 and said in lines[0], (
        f"expected exit 2 and one line with {said!r}, got exit {exported.returncode}:\n{exported.stderr}"
    )
    out = tmp_path / "run"
    ran = _toyroom("run", "--scenario", str(scenario), "--no-live", "--out", str(out))
    lines = ran.stderr.strip().splitlines()
    assert (
        ran.returncode == 2 and len(lines) == 1 and lines[0].startswith("toyroom run: ") and said in lines[0]
    ), f"expected exit 2 and one line with {said!r}, got exit {ran.returncode}:\n{ran.stderr}"
    left = sorted(p.name for p in tmp_path.iterdir())
    assert left == ["bad-id.toml", "paper.map.toml"], f"a refused run or export wrote something: {left}"


@pytest.mark.parametrize(
    ("table", "old", "new"),
    [
        ("regions", 'id = "S1"', 'id = "S 1"'),
        ("doors", 'id = "P1-S1"', 'id = "P1*S1"'),
        ("locations", 'id = "P1"\nregion = "P1"\ncell', 'id = "P\N{GRINNING FACE}"\nregion = "P1"\ncell'),
    ],
)
def test_the_map_loader_refuses_an_id_no_message_may_carry(
    tmp_path: Path, table: str, old: str, new: str
) -> None:
    text = (SCENARIOS / "paper.map.toml").read_text()
    assert old in text, f"paper's map changed ({old} is gone): update this test"
    (tmp_path / "paper.map.toml").write_text(text.replace(old, new, 1), encoding="utf-8")
    (tmp_path / "s.toml").write_text((SCENARIOS / "paper-1.toml").read_text())
    with pytest.raises(ScenarioError, match=rf"{table}\[\d+\]: id '.*' is not an id"):
        load_scenario(str(tmp_path / "s.toml"))
