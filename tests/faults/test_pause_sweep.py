"""An engine paused past its lease 20 times in a row, under load (a process burning a core
beside the engine and the brain), as an editor's breakpoint pauses it: one pause of a minute,
the others of 2.5 s, three times the nodes' default lease of 800 ms, so that the brain takes
the engine for gone in every one. The brain must come out of each pause one of two ways, never
a third: carry the episode on where it left off (an episode with pauses, once over, holds the
very states and events of one without, every tick once), or fail with one line that names the
pause: how long the brain waited, and for what (``waited N s for its answer to ...``). A pause
that catches a robot command before the engine answered it (paper-robot's robot acts) stops
the brain as soon as the engine is taken for gone, since whether the engine got the command
cannot be known (one of a run's 20 pauses was seen to). Both nodes have the default lease, so
the engine, continued, drops the brain's link before it reads the step the brain sent into the
pause in some pauses, and carries the step out first in the others: both ways a pause ends. A
failure starts a new brain on the same engine for the pauses left. (test_frozen_engine.py
pauses once, past ``toyroom run``'s 8 s lease, in ``make test``.)
"""

from __future__ import annotations

import subprocess
import sys
import threading
import time
from dataclasses import dataclass, field
from pathlib import Path

import pytest
from support import BrainProcess, EngineProcess, handled, pause

from bridge import Bridge
from protocol import State

pytestmark = [pytest.mark.process, pytest.mark.sweep]

PAUSES = 20
LONG_S = 60.0
"""The length of one pause (the :data:`LONG_AT`-th): a breakpoint held a minute."""
LONG_AT = 10
SHORT_S = 2.5
"""The length of the others: past the 800 ms lease three times over."""
FIRST, EVERY = 20, 25
"""The first pause of an episode comes at this tick, each next one this many ticks after the
brain carried on (paper-robot has 622: room for the 20)."""
OUTCOME_S = 90.0
"""Most seconds from the end of a pause to its outcome (the link is back within a second
unloaded); a brain that neither carries on nor fails in that time is what must not pass."""
CARRIED_ON = "the episode carries on"
"""What the brain logs once per pause it carries on from."""


@dataclass
class Ticks:
    """The newest (episode, tick) published on the engine's state."""

    seen: tuple[int, int] = (-1, -1)
    moved: threading.Condition = field(default_factory=threading.Condition)

    def on_state(self, state: State, _: object) -> None:
        with self.moved:
            self.seen = max(self.seen, (state.episode, state.tick))
            self.moved.notify_all()

    def wait_for(self, brain: BrainProcess, episode: int | None, tick: int, after: int) -> int | None:
        """The episode once the engine is at ``tick`` of ``episode`` (``None``: of an episode
        after ``after``, a new brain's); ``None`` when the brain exits first."""
        with self.moved:
            deadline = time.monotonic() + 120
            while not (
                (self.seen[0] == episode if episode is not None else self.seen[0] > after)
                and self.seen[1] >= tick
            ):
                if brain.process.poll() is not None:
                    return None
                assert time.monotonic() < deadline, f"no tick {tick} within 120 s:\n{brain.output()}"
                self.moved.wait(0.05)
            return self.seen[0]


def outcome(brain: BrainProcess, carried: int) -> str:
    """How the brain came out of the pause just ended (``carried``: how many it had carried on
    from before it): ``carried on, ...`` (how: the engine left where it was, or having carried
    out the step sent into the pause) or its failure line, having checked that it is one of
    the two allowed outcomes."""
    deadline = time.monotonic() + OUTCOME_S
    while brain.output().count(CARRIED_ON) <= carried and brain.process.poll() is None:
        assert time.monotonic() < deadline, (
            f"the brain neither carried on nor failed within {OUTCOME_S:g} s of the pause:\n{brain.output()}"
        )
        time.sleep(0.02)
    said = [line for line in brain.output().splitlines() if CARRIED_ON in line]
    if len(said) > carried:
        return "carried on, " + (
            "the step carried out in the pause" if "already" in said[-1] else "left there"
        )
    return failure(brain)


def failure(brain: BrainProcess) -> str:
    """The brain's failure line, having checked that there is one, naming the pause, and that
    the brain exited 2 with it."""
    status, output = brain.finish(30), brain.output()
    lines = [line for line in output.splitlines() if line.strip()]
    said = [line for line in lines if line.startswith("brain: ")]
    assert status == 2 and said == lines[-1:] and "Traceback" not in output, (
        f"a brain that does not carry on should exit 2 with one last line 'brain: ...'; it exited "
        f"{status}:\n{output}"
    )
    assert " s for its answer to " in said[0], (
        f"the line should name the pause (how long, for what): {said[0]}"
    )
    return said[0]


def test_an_engine_paused_20_times_under_load_is_carried_on_or_the_brain_says_why(
    world: str, tmp_path: Path
) -> None:
    burner = subprocess.Popen([sys.executable, "-c", "while True: pass"])
    try:
        with EngineProcess(world) as engine, Bridge(world) as watcher:
            ticks = Ticks()
            watcher.subscribe(watcher.keys.state, ticks.on_state, expected=State)
            with BrainProcess(
                world, "--scenario", "paper-robot", "--run-log", str(tmp_path / "base")
            ) as base:
                assert base.finish(300) == 0, f"the run without a pause failed:\n{base.output()}"
            outcomes = pause_in_turn(engine, ticks, tmp_path, handled(tmp_path / "base"))
    finally:
        burner.kill()
        burner.wait()
    carried = sum(1 for what in outcomes if what.startswith("carried on"))
    print(f"\n{len(outcomes)} pauses: {carried} carried on, {len(outcomes) - carried} failed with a line")
    for n, what in enumerate(outcomes, 1):
        print(f"  {n:2d} ({LONG_S if n == LONG_AT else SHORT_S:g} s): {what}")


def pause_in_turn(engine: EngineProcess, ticks: Ticks, folder: Path, base: list[dict]) -> list[str]:
    """Pause the engine :data:`PAUSES` times, each once the brain is :data:`EVERY` ticks past
    the last, in one episode while the brain carries on, in a new brain's after it fails: the
    outcome of each. An episode that ends is checked against ``base`` (the handled states and
    events of an episode without a pause)."""
    outcomes: list[str] = []
    while len(outcomes) < PAUSES:
        log = folder / f"brain-{len(outcomes) + 1}"
        before = ticks.seen[0]
        with BrainProcess(engine.world, "--scenario", "paper-robot", "--run-log", str(log)) as brain:
            episode, tick = None, FIRST
            while len(outcomes) < PAUSES:
                episode = ticks.wait_for(brain, episode, tick, before)
                if episode is None:
                    break
                carried = brain.output().count(CARRIED_ON)
                pause(engine.process, LONG_S if len(outcomes) + 1 == LONG_AT else SHORT_S)
                outcomes.append(outcome(brain, carried))
                if not outcomes[-1].startswith("carried on"):
                    break
                tick = ticks.seen[1] + EVERY
            finished(brain, log, base, outcomes)
    return outcomes


def finished(brain: BrainProcess, log: Path, base: list[dict], outcomes: list[str]) -> None:
    """Check how a brain of the sweep ended: having carried the episode on (exit 0), with the
    states and events of ``base``; or failed, with its line (which replaces the last outcome
    when the brain said it carried on, then failed asking the step again)."""
    if brain.process.poll() not in (None, 0):
        line = failure(brain)
        if outcomes and outcomes[-1].startswith("carried on"):
            outcomes[-1] = line
        return
    status = brain.finish(300)
    assert status == 0, f"the brain failed after carrying on from its pauses:\n{brain.output()}"
    got = handled(log)
    first = next(
        (i for i, (a, b) in enumerate(zip(got, base, strict=False)) if a != b), min(len(got), len(base))
    )
    assert got == base, (
        f"the brain carried the episode on, so the {len(base)} states and events of the episode "
        f"without a pause were expected; it handled {len(got)}, the first difference at #{first}: "
        f"{got[first : first + 1]} instead of {base[first : first + 1]}"
    )
