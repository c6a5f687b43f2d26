"""The viewer follows the engine: when an engine for its world comes back (with another
scene), it shakes hands again and redraws the map."""

from __future__ import annotations

import threading
import time

from support import EngineProcess

from toyroom.view import Viewer


def wait_for(predicate, timeout: float) -> bool:  # type: ignore[no-untyped-def]
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if predicate():
            return True
        time.sleep(0.05)
    return False


def test_viewer_redraws_when_a_new_engine_appears(world: str) -> None:
    viewer = Viewer(world)
    runner = threading.Thread(target=viewer.run, daemon=True)
    runner.start()
    try:
        with EngineProcess(world, "--scenario", "paper-1"):
            assert wait_for(lambda: viewer.info is not None and viewer.info.scenario == "paper-1", 30)
            assert viewer.view.scene is not None and viewer.view.scene.name == "paper"
        with EngineProcess(world, "--scenario", "sally-anne"):
            assert wait_for(lambda: viewer.info is not None and viewer.info.scenario == "sally-anne", 30), (
                f"the viewer still shows {viewer.info.scenario if viewer.info else None}"
            )
            assert viewer.view.scene is not None and viewer.view.scene.name == "sally-anne"
    finally:
        viewer.close()
        runner.join(timeout=5)
