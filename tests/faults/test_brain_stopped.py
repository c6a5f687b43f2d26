"""A brain stopped with SIGTERM before its episode's end (as ``toyroom play`` stops one when a
study's goal is reached, or a participant leaves) writes its outputs for the ticks it saw,
says so in its report, and exits 0: nothing it inferred is lost."""

from __future__ import annotations

import signal
import subprocess
import sys
import threading
from pathlib import Path

from support import EngineProcess, MindCsv

from bridge import Bridge
from protocol import Mind


def test_a_brain_stopped_early_writes_what_it_has(world: str, tmp_path: Path) -> None:
    out = tmp_path / "out"
    seen = threading.Event()
    with EngineProcess(world, "--scenario", "paper-2", "--lockstep") as _, Bridge(world) as bridge:
        bridge.subscribe(bridge.keys.mind, lambda m, _: seen.set() if m.tick >= 40 else None, expected=Mind)
        brain = subprocess.Popen(
            [sys.executable, "-m", "brain", "--world", world, "--scenario", "paper-2", "--out", str(out),
             "--log-level", "WARNING"],
            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
        )  # fmt: skip
        try:
            assert seen.wait(120), "the brain published no mind of tick 40 within 120 s"
            brain.send_signal(signal.SIGTERM)
            output, _ = brain.communicate(timeout=120)
        finally:
            if brain.poll() is None:
                brain.kill()
                brain.wait()
    assert brain.returncode == 0, f"a brain stopped with SIGTERM exited {brain.returncode}: {output}"
    assert "stopped (SIGTERM) at tick" in output, f"the brain did not say it was stopped: {output}"
    mind = MindCsv(out / "mind.csv")
    last = max(int(r["tick"]) for r in mind.rows)
    assert 40 <= last < 900, f"mind.csv should end where the brain was stopped (tick 40 on), ends at {last}"
    report = (out / "report.md").read_text(encoding="utf-8")
    assert "before the episode's end" in report, (
        f"the report does not say the run was cut short: {report[:400]}"
    )
