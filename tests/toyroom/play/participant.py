"""A scripted participant of ``toyroom play``'s page (headless Chromium over the DevTools
protocol): pressing Start, walking to places, and playing ``paper-robot`` as A1 to its goal."""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Any

from bridge import Bridge
from protocol import Event
from tests.toyroom.devtools import Tab, wait_until

VIEW = "window.playState && window.playState.view"


def view(tab: Tab) -> dict[str, Any]:
    return dict(tab.evaluate(f"{VIEW} ? JSON.parse(JSON.stringify({VIEW})) : null") or {})


def press_start(tab: Tab) -> None:
    """Wait for the page's instructions, press Start and wait until the world runs."""
    tab.wait_for(f"{VIEW} && {VIEW}.tick >= 0 && window.playState.scene", 180, "the first view")
    tab.wait_for("document.getElementById('intro').style.display === 'block'", 30, "the instructions")
    tab.evaluate("document.getElementById('start').click()")
    hidden = "document.getElementById('intro').style.display === 'none'"
    tab.wait_for(f"{VIEW}.started && {hidden}", 30, "the start")


def at(tab: Tab, xy: tuple[float, float], what: str, timeout: float = 60) -> None:
    def there() -> bool:
        me = next((a for a in view(tab).get("agents", []) if a["you"]), None)
        return me is not None and abs(me["x"] - xy[0]) < 0.05 and abs(me["y"] - xy[1]) < 0.05

    try:
        wait_until(there, timeout, what)
    except AssertionError:
        mine = [a for a in view(tab).get("agents", []) if a["you"]]
        raise AssertionError(f"waited {timeout:g} s for {what} at {xy}; the person is at {mine}") from None


def goto(tab: Tab, key: str, xy: tuple[float, float], what: str) -> None:
    """Press ``key`` and wait until the person stands at ``xy``; as a participant would, press
    it again once when the person has not set off after 10 s (on a loaded 2-core machine a
    Zenoh link has been seen to drop a command)."""
    tab.press(key)
    try:
        at(tab, xy, what, timeout=10)
    except AssertionError:
        tab.press(key)
        at(tab, xy, what)


def go_out_and_back(tab: Tab, outside: Callable[[], None] | None = None) -> None:
    """A1's part of ``paper-robot`` as its instructions ask: play with the skate, leave it on the
    Storage 1 shelf, go outside (``outside``: called there), wait for A2's swap and come back to
    the shelf."""
    world = tab.evaluate("window.playState.scene.world")
    swapped = threading.Event()
    with Bridge(world) as bridge:
        bridge.subscribe(
            bridge.keys.events,
            lambda e, _: swapped.set() if e.actor == "A2" and e.label == "swapped" else None,
            expected=Event,
        )
        tab.press("p")
        start = tab.wait_for(f"{VIEW}.playing && {VIEW}.tick", 30, "A1 playing with the skate")
        tab.wait_for(f"{VIEW}.tick >= {start + 20}", 30, "20 ticks of play")
        goto(tab, "2", (5.5, 10.5), "A1 at the Storage 1 shelf")
        tab.press("d")
        tab.wait_for(f"!({VIEW}.holding)", 30, "the skate dropped")
        goto(tab, "5", (5.5, 6.5), "A1 in the entrance (its cell nearest Storage 1)")
        goto(tab, "6", (7.5, 2.5), "A1 outside (its cell nearest the entrance)")
        if outside is not None:
            outside()
        assert swapped.wait(120), "A2 never swapped the ball for the skate (A1's label 4 not completed?)"
    goto(tab, "5", (7.5, 4.5), "A1 back in the entrance")
    goto(tab, "2", (5.5, 10.5), "A1 back at the Storage 1 shelf")


def play_paper_robot_to_the_goal(tab: Tab) -> str:
    """Start, :func:`go_out_and_back`, then a yes to the robot's offer of the skate; the page's
    ``ended`` once the world ends (``goal reached``)."""
    press_start(tab)
    go_out_and_back(tab)
    tab.wait_for(f"{VIEW}.question && {VIEW}.question.kind === 'give'", 240, "the robot's offer of the skate")
    tab.press("y")
    return str(tab.wait_for(f"{VIEW}.ended", 120, "the end of the episode"))
