"""How fast the live view draws the paper map: the median and p99 time of one frame (moving
every body and redrawing every overlay) on a recorded paper-robot run. The view draws at
most 30 frames a second, so it keeps up while a frame takes under 33 ms.

    python bench/view_bench.py
"""

from __future__ import annotations

import statistics
import time

from rich.console import Console
from rich.table import Table

from brain.outputs.results import mind_message
from brain.tracking.tracker import MindTracker
from bridge.view import SceneView
from sim2d.engine import Engine


def main() -> dict[str, float]:
    import meshcat

    engine = Engine("paper-robot")
    tracker = MindTracker(engine.scene())
    frames = []
    state = engine.state()
    while not engine.done and state.tick < 300:
        result = engine.step()
        state = result.state
        tracker.observe(state, result.events)
        frames.append((state, mind_message(tracker, state)))
    vis = meshcat.Visualizer()
    try:
        view = SceneView(vis)
        view.draw_scene(engine.scene())
        times = []
        for state, mind in frames:
            view.on_state(state, None)  # type: ignore[arg-type]
            view.on_mind(mind, None)  # type: ignore[arg-type]
            start = time.perf_counter()
            view.render()
            times.append(time.perf_counter() - start)
    finally:
        vis.window.server_proc.terminate()
    times.sort()
    numbers = {
        "frame_ms_median": statistics.median(times) * 1e3,
        "frame_ms_p99": times[int(0.99 * (len(times) - 1))] * 1e3,
    }
    table = Table(title=f"meshcat view, paper map, {len(times)} frames")
    table.add_column("measure")
    table.add_column("ms", justify="right")
    table.add_row("frame, median", f"{numbers['frame_ms_median']:.1f}")
    table.add_row("frame, p99", f"{numbers['frame_ms_p99']:.1f}")
    table.add_row("budget at 30 Hz", "33.3")
    Console().print(table)
    return numbers


if __name__ == "__main__":
    main()
