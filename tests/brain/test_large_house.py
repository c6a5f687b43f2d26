"""A 10-room house with 6 items end to end: engine and brain processes in lock-step, the
brain on the factored model (it says so in its report), the robot acting on its estimates."""

from __future__ import annotations

from pathlib import Path

from support import MindCsv, toyroom_run

from protocol import EpisodeSpec
from sim2d.generation import write_house_episode


def test_toyroom_run_on_a_ten_room_six_item_house(tmp_path: Path) -> None:
    scenario = write_house_episode(tmp_path / "scenario", 10, 6, 5, EpisodeSpec(max_ticks=150))
    out = toyroom_run(tmp_path / "run", str(scenario), "--robot", "act", "--no-live")
    report = (out / "report.md").read_text()
    assert "factored model" in report, f"the report should say the factored model ran:\n{report}"
    mind = MindCsv(out / "mind.csv")
    items = {row["item"] for row in mind.rows if row["quantity"] == "belief"}
    assert len(items) == 6, f"beliefs about 6 items expected, got {sorted(items)}"
    ticks = {int(row["tick"]) for row in mind.rows}
    assert max(ticks) >= 140, f"the run should reach the episode's end (150 ticks), got {max(ticks)}"
