"""The ``oracle`` policy end to end (engine and brain processes over loopback Zenoh): the robot
reads the simulated people's true minds off ``engine/truth`` and acts for the person with a
false belief; against an engine that publishes no truth the brain refuses at its handshake."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

from support import EventsCsv, toyroom_run


def test_the_oracle_tells_the_person_with_a_false_belief(tmp_path: Path) -> None:
    """A ``moved`` task episode (seed 1): A2 moves the ball A1 will come back for. The oracle
    reads A1's true false belief and tells A1 where the ball is now."""
    generated = subprocess.run(
        [sys.executable, "-m", "sim2d", "generate", "--kind", "tasks", "--tasks", "moved"]
        + ["--seed", "1", "--max-ticks", "300", "--out", str(tmp_path)],
        capture_output=True,
        text=True,
        timeout=120,
    )
    assert generated.returncode == 0, generated.stderr
    scenario = generated.stdout.strip().splitlines()[-1]
    out = toyroom_run(tmp_path / "run", scenario, "--set", "policy=oracle")
    events = EventsCsv(out / "events.csv")
    drop = events.find(actor="A2", kind="drop", item="ball")[-1]
    told = events.find(actor="robot", kind="say", item="ball", target="A1", location=drop["location"])
    assert told, f"the oracle never told A1 the ball is at {drop['location']}"
    taken = [int(r["tick"]) for r in events.find(actor="A1", kind="take", item="ball")] or [10**9]
    assert int(drop["tick"]) < int(told[0]["tick"]) < taken[-1], (drop, told[0], taken)
    assert (out / "mind.csv").is_file(), "the brain's own inference is still written"


def test_the_oracle_against_an_engine_without_truth_fails_at_once(tmp_path: Path) -> None:
    """``paper-robot``'s people are scripted: sim2d publishes no truth (no ``truth``
    capability), so the brain exits 2 with one line saying so."""
    result = subprocess.run(
        [sys.executable, "-m", "toyroom", "run", "--scenario", "paper-robot", "--set", "policy=oracle"]
        + ["--out", str(tmp_path), "--no-live", "--timeout", "60"],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert result.returncode != 0, result.stdout
    assert "the brain exited with status 2" in result.stderr, result.stderr
    assert "publishes none (no 'truth' capability in its handshake)" in result.stderr, result.stderr
