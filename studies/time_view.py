"""How fast the live view draws the paper map, on a paper-robot run (300 ticks): the median
and p99 time of one frame (moving every body) and of one redraw of the brain's estimates
(every bar, ring and dot, and the minds panel's text, drawn into a PNG and sent). The view
moves bodies at most 30 times a second (33 ms each) and redraws estimates at most 5 times a
second (200 ms), so it keeps up while each takes less.

    python studies/time_view.py
"""

from __future__ import annotations

import statistics
import time

from rich.console import Console
from rich.table import Table

from brain.outputs.results import mind_message
from brain.tracking.tracker import MindTracker
from bridge.processes import stop_process_group
from sim2d.engine import Engine
from toyroom.view import SceneView
from toyroom.view.server import start_server


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
    server, zmq_url = start_server()  # on 127.0.0.1 only
    try:
        vis = meshcat.Visualizer(zmq_url=zmq_url)
        view = SceneView(vis)
        scene = engine.scene()
        view.draw_scene(scene)
        times: list[float] = []
        minds: list[float] = []
        for state, mind in frames:
            start = time.perf_counter()
            view.move_bodies(state)
            times.append(time.perf_counter() - start)
            start = time.perf_counter()
            view.draw_mind(scene, state, mind)
            minds.append(time.perf_counter() - start)
    finally:
        stop_process_group(server)
    times.sort()
    minds.sort()
    numbers = {
        "frame_ms_median": statistics.median(times) * 1e3,
        "frame_ms_p99": times[int(0.99 * (len(times) - 1))] * 1e3,
        "mind_ms_median": statistics.median(minds) * 1e3,
        "mind_ms_p99": minds[int(0.99 * (len(minds) - 1))] * 1e3,
    }
    table = Table(title=f"meshcat view, paper map, {len(times)} frames")
    table.add_column("measure")
    table.add_column("ms", justify="right")
    table.add_row("frame, median", f"{numbers['frame_ms_median']:.1f}")
    table.add_row("frame, p99", f"{numbers['frame_ms_p99']:.1f}")
    table.add_row("budget at 30 Hz", "33.3")
    table.add_row("estimates, median", f"{numbers['mind_ms_median']:.1f}")
    table.add_row("estimates, p99", f"{numbers['mind_ms_p99']:.1f}")
    table.add_row("budget at 5 Hz", "200.0")
    Console().print(table)
    return numbers


if __name__ == "__main__":
    main()
