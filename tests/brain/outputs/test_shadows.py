"""Shadow observers: the minds a brain writes for another observer are exactly what a live
brain with that observer publishes on the same episode (what ``toyroom eval`` relies on)."""

from __future__ import annotations

import threading
import time
from pathlib import Path

import msgspec
from support import EngineProcess, run_brain

from bridge import Bridge, Received
from protocol import Mind, decode

TICKS = 150


def live_minds(world: str, observer: str, *extra: str) -> dict[int, Mind]:
    """Run a lock-step brain with ``observer`` for ``TICKS`` ticks; its minds from the wire."""
    minds: dict[int, Mind] = {}
    lock = threading.Lock()

    def keep(mind: Mind, _: Received) -> None:
        with lock:
            minds[mind.tick] = mind

    with Bridge(world) as watcher:
        watcher.subscribe(watcher.keys.mind, keep, expected=Mind)
        brain = run_brain(
            world, "--scenario", "paper-auto", "--observer", observer, "--max-ticks", str(TICKS), *extra
        )
        assert brain.returncode == 0, brain.stderr
        deadline = time.monotonic() + 10
        while time.monotonic() < deadline and max(minds, default=-1) < TICKS:
            time.sleep(0.05)
    with lock:
        return dict(minds)


def people(mind: Mind) -> Mind:
    """The people's part of a mind (a shadow reports no robot activity; each run resets the
    engine, so the episode number differs)."""
    return msgspec.structs.replace(mind, robots=(), episode=0)


def file_minds(path: Path) -> dict[int, Mind]:
    return {m.tick: people(m) for m in (decode(line, Mind) for line in path.read_bytes().splitlines())}


def test_shadow_minds_equal_a_live_brain_of_that_observer(world: str, tmp_path: Path) -> None:
    with EngineProcess(world, "--scenario", "paper-auto", "--lockstep"):
        btom = live_minds(
            world, "btom", "--shadow", "btom", "--shadow", "perceptonly", "--shadow-out", str(tmp_path)
        )
        perceptonly = live_minds(world, "perceptonly")
    shadow_btom = file_minds(tmp_path / "minds-btom.jsonl")
    shadow_perceptonly = file_minds(tmp_path / "minds-perceptonly.jsonl")
    assert sorted(shadow_btom) == list(range(TICKS + 1)), (
        f"ticks 0..{TICKS} expected, got {sorted(shadow_btom)}"
    )
    for tick in sorted(btom):  # the wire may drop nothing here, but only compare what came
        assert shadow_btom[tick] == people(btom[tick]), (
            f"tick {tick}: shadow {shadow_btom[tick]} != live {btom[tick]}"
        )
    assert len(btom) > TICKS // 2, f"only {len(btom)} live minds arrived"
    for tick in sorted(perceptonly):
        assert shadow_perceptonly[tick] == people(perceptonly[tick]), (
            f"tick {tick}: shadow perceptonly {shadow_perceptonly[tick]} != live {perceptonly[tick]}"
        )
    assert shadow_perceptonly != shadow_btom, "the two observers should differ somewhere"
