"""The meshcat view in headless Chromium: people, items and belief bars are drawn, and the
false-belief highlight shows in sally-anne after Anne's unseen move and not before.

:func:`shot_at` is shared: it replays a recording into a fresh world and has the viewer take
its screenshot as soon as it has drawn the tick asked for (``--tick``), not after a sleep."""

from __future__ import annotations

import json
import subprocess
import sys
import uuid
from pathlib import Path

import matplotlib.image
import numpy as np
from support import EventsCsv, toyroom_run

from bridge.recording import read_recording
from protocol import ItemShape
from toyroom.view import BAR_COLOURS, HALO_COLOUR, ITEM_COLOURS, PANEL_FRACTION, PERSON_COLOURS


def pixels_of(image: np.ndarray, colour: int, tolerance: float = 8 / 255) -> int:
    rgb = np.array([(colour >> 16) & 255, (colour >> 8) & 255, colour & 255]) / 255
    return int(np.all(np.abs(image[:, :, :3] - rgb) <= tolerance, axis=2).sum())


def map_part(image: np.ndarray) -> np.ndarray:
    """The left of a screenshot, where the map is (the panels, right of it, show the legend's
    colour samples)."""
    return image[:, : int(image.shape[1] * (1 - PANEL_FRACTION))]


def pace(recording: Path, until: int, seconds: float = 3.0) -> float:
    """The replay speed that spreads ``recording`` up to tick ``until`` over about
    ``seconds``: a lock-step run is recorded at hundreds of ticks a second, and replayed as
    fast, its messages (sent drop-on-congestion) would overrun a busy viewer."""
    records = read_recording(recording).records
    last = records[0].log_time
    for record in records:
        tick = json.loads(record.data).get("tick") if record.data.startswith(b"{") else None
        if isinstance(tick, int) and tick > until:
            break
        last = record.log_time
    return max((last - records[0].log_time) / 1e9 / seconds, 1e-3)


def shot_at(recording: Path, tick: int, out: Path, *extra: str, until: int | None = None) -> np.ndarray:
    """Start the viewer on a fresh world, replay ``recording`` into it up to tick ``until``
    (default ``tick``) over about three seconds, and take the viewer's screenshot once it
    has drawn a mind of ``tick`` or later (a window of ticks after ``tick`` makes one
    arriving all but certain; the replay also sends its last mind once more)."""
    until = tick if until is None else until
    world = f"view-{uuid.uuid4().hex[:8]}"
    view = ["view", "--world", world, "--screenshot", str(out), "--tick", str(tick), "--after", "90", *extra]
    viewer = subprocess.Popen(
        [sys.executable, "-m", "toyroom", *view],
        stdout=subprocess.PIPE,
        stderr=subprocess.PIPE,
        text=True,
    )
    replay = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "toyroom",
            "replay",
            str(recording),
            "--world",
            world,
            "--speed",
            f"{pace(recording, until):.6f}",
            "--until-tick",
            str(until),
            "--hold",
            "--wait-subscribers",
            "60",
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

    before = map_part(shot_at(recording, taken - 20, tmp_path / "before.png", until=taken - 5))
    for name, colour in (
        ("Sally", PERSON_COLOURS[0]),
        ("Anne", PERSON_COLOURS[1]),
        ("the marble", ITEM_COLOURS[ItemShape.MARBLE]),
        ("Sally's belief bars", BAR_COLOURS[0]),
    ):
        assert pixels_of(before, colour) > 20, f"{name} not drawn (no pixels of #{colour:06x})"
    assert pixels_of(before, HALO_COLOUR) == 0, "a false-belief highlight before Anne moved the marble"

    after = map_part(shot_at(recording, moved + 5, tmp_path / "after.png", until=moved + 20))
    assert pixels_of(after, HALO_COLOUR) > 20, "no false-belief highlight after Anne's unseen move"
