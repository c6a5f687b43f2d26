"""The meshcat view in headless Chromium: people, items and belief bars are drawn, and the
false-belief highlight shows in sally-anne after Anne's unseen move and not before."""

from __future__ import annotations

import subprocess
import sys
import uuid
from pathlib import Path

import matplotlib.image
import numpy as np
from support import EventsCsv, toyroom_run

from bridge.view import BAR_COLOURS, HALO_COLOUR, ITEM_COLOURS, PERSON_COLOURS
from protocol import ItemShape


def pixels_of(image: np.ndarray, colour: int, tolerance: float = 8 / 255) -> int:
    rgb = np.array([(colour >> 16) & 255, (colour >> 8) & 255, colour & 255]) / 255
    return int(np.all(np.abs(image[:, :, :3] - rgb) <= tolerance, axis=2).sum())


def shot_at(recording: Path, tick: int, out: Path) -> np.ndarray:
    """Start the viewer on a fresh world, replay ``recording`` into it up to ``tick``, and
    take the viewer's screenshot."""
    world = f"view-{uuid.uuid4().hex[:8]}"
    viewer = subprocess.Popen(
        [sys.executable, "-m", "bridge", "view", "--world", world, "--screenshot", str(out), "--after", "6"],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    replay = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "bridge",
            "replay",
            str(recording),
            "--world",
            world,
            "--speed",
            "0",
            "--until-tick",
            str(tick),
            "--hold",
            "--wait-subscribers",
            "10",
        ],
        stdout=subprocess.PIPE,
        text=True,
    )
    try:
        _, err = viewer.communicate(timeout=180)
        assert viewer.returncode == 0, err
    finally:
        replay.terminate()
        replay.wait(timeout=10)
    return matplotlib.image.imread(str(out))


def test_view_draws_the_scene_and_the_false_belief(tmp_path: Path) -> None:
    recording = tmp_path / "sally.mcap"
    run = toyroom_run(tmp_path / "run", "sally-anne", "--robot", "observe", "--record", str(recording))
    events = EventsCsv(run / "events.csv")
    taken = events.first_tick(actor="anne", kind="take", item="marble")
    moved = events.first_tick(actor="anne", kind="drop", item="marble", location="box")

    before = shot_at(recording, taken - 5, tmp_path / "before.png")
    for name, colour in (
        ("Sally", PERSON_COLOURS[0]),
        ("Anne", PERSON_COLOURS[1]),
        ("the marble", ITEM_COLOURS[ItemShape.MARBLE]),
        ("Sally's belief bars", BAR_COLOURS[0]),
    ):
        assert pixels_of(before, colour) > 20, f"{name} not drawn (no pixels of #{colour:06x})"
    assert pixels_of(before, HALO_COLOUR) == 0, "a false-belief highlight before Anne moved the marble"

    after = shot_at(recording, moved + 10, tmp_path / "after.png")
    assert pixels_of(after, HALO_COLOUR) > 20, "no false-belief highlight after Anne's unseen move"
