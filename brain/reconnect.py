"""A lock-step engine lost and back: whether the episode can carry on, and a robot command's
answer awaited while the engine may go away.

An engine stalled past its link's lease (a loaded machine, SIGSTOP) or killed is lost to the
brain; what it did meanwhile never reaches the brain. Back where the brain left it (the same
episode and tick), nothing was missed and the episode carries on; further on in the same
episode, it stepped while the link was down and those ticks are lost: the brain stops rather
than follow an episode with a hole in it. The same holds for a command sent while the engine
was going: whether it arrived cannot be known, so the brain stops.
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


def where_left(clock: LockstepClient, engine: str, state: State) -> bool:
    """Whether the lock-step engine that is back is where the brain left it (``state``'s
    episode and tick), so the episode carries on; ``False`` for a restarted engine (another
    episode, or an earlier tick).

    Raises:
        BrainError: it is further on in ``state``'s episode: it stepped while the link was
            down, and what happened on those ticks is lost.
        StepTimeout: it does not say where it is.
    """
    now = clock.where()
    if (now.episode, now.tick) == (state.episode, state.tick):
        log.warning(
            "engine '%s' is where the brain left it (episode %d, tick %d): the episode carries on",
            engine,
            state.episode,
            state.tick,
        )
        return True
    if now.episode == state.episode and now.tick > state.tick:
        raise BrainError(
            f"engine '{engine}' stepped from tick {state.tick} to {now.tick} of episode {state.episode} "
            "while its link to the brain was down (a stall?): what happened on those ticks is lost, "
            "so the episode cannot carry on"
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
    deadline = None if timeout is None else time.monotonic() + timeout
    while not book.answered(command):
        remaining = None if deadline is None else deadline - time.monotonic()
        if remaining is not None and remaining <= 0:
            raise StepTimeout(f"the engine never answered robot command '{command}' within {timeout:g} s")
        if lost is not None and lost.is_set():
            drain(robot, inbox)
            if book.answered(command):
                return
            raise BrainError(
                "the engine was lost (killed, or stalled past its link's lease) before it answered "
                f"robot command '{command}': whether it has the command cannot be known, so the "
                "episode cannot carry on"
            )
        try:
            robot.record(inbox.get(timeout=POLL_S if remaining is None else min(remaining, POLL_S)))
        except queue.Empty:
            continue
