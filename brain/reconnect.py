"""A lock-step engine lost and back: whether the episode can carry on, and a robot command's
answer awaited while the engine may go away.

An engine stalled past its link's lease (paused at a breakpoint, SIGSTOP, a loaded machine) or
killed is lost to the brain; what it publishes meanwhile never reaches the brain. A lock-step
engine moves only when asked, so one that was paused comes back where the brain left it, or
one step on: continued, it still reads the step the brain sent before the link went down and
carries it out, its answer lost with the link (whether it reads the step or drops the link
first is a race). Either way the brain asks that step again under its request id
(:meth:`bridge.LockstepClient.again`): the engine carries it out now, or answers with the
answer it gave, and the episode carries on with every tick. Further on in the same episode,
it stepped while the link was down and those ticks are lost: the brain stops rather than
follow an episode with a hole in it. A command sent while the engine was going is another
matter: whether it arrived cannot be known, so the brain stops.
"""

from __future__ import annotations

import logging
import queue
import threading
import time

from bridge import LockstepClient, StepTimeout
from protocol import CommandStatus, State

from .errors import BrainError
from .robot.controller import RobotBrain

log = logging.getLogger("toyroom.brain")

POLL_S = 0.1
"""Seconds between two looks at the engine's liveliness while a command awaits its answer."""


def waited_for(clock: LockstepClient, state: State) -> str:
    """What the brain was waiting for while the engine was away, and how long it has waited,
    e.g. ``the brain waited 61.3 s for its answer to step 1 from tick 200 of episode 1``."""
    asked = clock.unanswered
    if asked is None:
        return f"the brain had handled tick {state.tick} of episode {state.episode}"
    waited = time.monotonic() - asked.sent_at
    return (
        f"the brain waited {waited:.1f} s for its answer to {asked} from tick {state.tick} of "
        f"episode {state.episode}"
    )


def rejoins(clock: LockstepClient, engine: str, state: State) -> bool:
    """Whether the lock-step engine that is back can carry on ``state``'s episode (``state``:
    the last the brain handled): it is where the brain left it, or as far on as the step the
    brain was waiting for (it carried that step out); :func:`ask_again` then gets that step's
    answer. ``False`` for a restarted engine (another episode, or an earlier tick).

    Raises:
        BrainError: it is further on in ``state``'s episode: it stepped while the link was
            down, and what happened on those ticks is lost.
        StepTimeout: it does not say where it is.
    """
    now = clock.where()
    asked = clock.unanswered
    ahead = now.tick - state.tick
    if now.episode == state.episode and 0 <= ahead <= (asked.ticks if asked is not None else 0):
        carried = f"it carried out {asked} already" if ahead else "where the brain left it"
        log.warning(
            "engine '%s' is back at tick %d of episode %d, %s (%s): asking again, the episode carries on",
            engine,
            now.tick,
            now.episode,
            carried,
            waited_for(clock, state),
        )
        return True
    if now.episode == state.episode and ahead > 0:
        raise BrainError(
            f"engine '{engine}' came back at tick {now.tick} of episode {state.episode} after a pause "
            f"({waited_for(clock, state)}): it stepped on while its link to the brain was down, and what "
            f"happened on ticks {state.tick + 1}-{now.tick} is lost, so the episode cannot carry on"
        )
    log.warning(
        "engine '%s' is in episode %d at tick %d, not where the brain left it (episode %d, tick %d): "
        "it was restarted; starting the episode again",
        engine,
        now.episode,
        now.tick,
        state.episode,
        state.tick,
    )
    return False


def ask_again(clock: LockstepClient, engine: str, state: State) -> State:
    """The state after the step the brain was waiting for when the engine went (``state``: the
    one before it), asked again under its request id (a fresh step when none is unanswered).

    Raises:
        BrainError: the answer is not the tick after ``state``: the engine carried the step
            out a second time (an engine that keeps no answers by request id), so a tick is lost.
        StepTimeout: no answer.
    """
    asked = clock.unanswered
    if asked is None:
        return clock.step(1)
    expected, waited = state.tick + asked.ticks, waited_for(clock, state)
    got = clock.again()
    if (got.episode, got.tick) != (state.episode, expected):
        raise BrainError(
            f"engine '{engine}' came back from a pause ({waited}) and, asked again, answered tick "
            f"{got.tick} of episode {got.episode}, not tick {expected}: it carried the step out twice "
            "(an engine that keeps no answers by request id), and what happened on the ticks between "
            "is lost, so the episode cannot carry on"
        )
    return got


def drain(robot: RobotBrain, inbox: queue.Queue[CommandStatus]) -> None:
    """Record every status waiting in ``inbox``."""
    while True:
        try:
            robot.record(inbox.get_nowait())
        except queue.Empty:
            return


def await_receipt(
    robot: RobotBrain,
    inbox: queue.Queue[CommandStatus],
    command: str,
    timeout: float | None,
    lost: threading.Event | None,
) -> None:
    """Wait until the engine has accepted or refused ``command`` (keeps runs reproducible),
    at most ``timeout`` seconds (``None``: no limit), looking every :data:`POLL_S` s at
    ``lost`` (set while no engine is alive).

    Raises:
        StepTimeout: no answer within the timeout.
        BrainError: the engine was lost before it answered: whether it has the command cannot
            be known.
    """
    book = robot.tree.context.book
    sent = time.monotonic()
    deadline = None if timeout is None else sent + timeout
    while not book.answered(command):
        remaining = None if deadline is None else deadline - time.monotonic()
        if remaining is not None and remaining <= 0:
            raise StepTimeout(f"the engine never answered robot command '{command}' within {timeout:g} s")
        if lost is not None and lost.is_set():
            drain(robot, inbox)
            if book.answered(command):
                return
            raise BrainError(
                "the engine was lost (killed, or stalled past its link's lease) while the brain "
                f"waited {time.monotonic() - sent:.1f} s for its answer to robot command '{command}': "
                "whether it has the command cannot be known, so the episode cannot carry on"
            )
        try:
            robot.record(inbox.get(timeout=POLL_S if remaining is None else min(remaining, POLL_S)))
        except queue.Empty:
            continue
