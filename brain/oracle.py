"""The ``oracle`` robot's wire: the engine's truths (``engine/truth``), tick by tick, for a
robot that reads the simulated people's true minds (an upper bound, not a robot one could
build; :mod:`brain.robot.oracle` reads the estimates off them).

Only an engine whose handshake lists the ``truth`` capability publishes truths (sim2d, with
autonomous people): against any other the oracle fails at its handshake after the reset,
before the first tick (:func:`oracle_minds`; ``python -m brain`` exits 2 with that one line).
The node subscribes before it resets the engine (:func:`truth_feed`), so tick 0's truth is
heard too. Each tick the robot waits, a bounded wait, for that tick's own truth: a truth
travels beside the step's answer, not in it, and may come after it; the robot never decides
on an older one (lock-step runs repeat), and a truth that never comes fails the run.
"""

from __future__ import annotations

import threading
from collections.abc import Callable, Mapping

from bridge import Bridge, Received
from protocol import Capability, EngineInfo, Policy, RobotMode, State, Truth

from .errors import BrainError
from .model.estimates import Estimate
from .robot.oracle import oracle_estimates
from .settings import RobotSettings
from .tracking.tracker import MindTracker

KEEP = 256
"""The most truths kept unread (a robot reads each tick's, and forgets the older ones)."""


class OracleError(BrainError):
    """The ``oracle`` policy without the engine's truth: no ``truth`` capability, or a tick's
    truth that never came."""


class TruthFeed:
    """The engine's truths by ``(episode, tick)``, heard on ``engine/truth``; :meth:`at` waits
    (at most ``wait`` seconds; ``None``: no limit) for one tick's. Close it to unsubscribe."""

    def __init__(self, bridge: Bridge, wait: float | None) -> None:
        self.key = bridge.keys.truth
        self.wait = wait
        self._cond = threading.Condition()
        self._truths: dict[tuple[int, int], Truth] = {}
        self._subscriber = bridge.subscribe(self.key, self._on_truth, expected=Truth)

    def _on_truth(self, truth: Truth, _: Received) -> None:
        with self._cond:
            self._truths[(truth.episode, truth.tick)] = truth
            while len(self._truths) > KEEP:
                del self._truths[min(self._truths)]
            self._cond.notify_all()

    def at(self, episode: int, tick: int) -> Truth:
        """The truth of engine tick ``tick`` of ``episode``, once it is here; the older ones
        are forgotten.

        Raises:
            OracleError: it did not come within ``wait`` seconds.
        """
        key = (episode, tick)
        with self._cond:
            if not self._cond.wait_for(lambda: key in self._truths, self.wait):
                raise OracleError(
                    f"the oracle policy had no truth of episode {episode} tick {tick} on '{self.key}' "
                    f"within {self.wait:g} s: the engine stopped publishing the people's true minds"
                )
            for older in [k for k in self._truths if k < key]:
                del self._truths[older]
            return self._truths[key]

    def close(self) -> None:
        self._subscriber.close()


def truth_feed(
    bridge: Bridge, settings: RobotSettings, robot: RobotMode | None, wait: float | None
) -> TruthFeed | None:
    """A :class:`TruthFeed` when the robot acts by the ``oracle`` policy (``robot``: the node's
    ``act``/``observe`` override, ``None``: as the scene says), else ``None``."""
    if settings.policy != Policy.ORACLE or robot == RobotMode.OBSERVE:
        return None
    return TruthFeed(bridge, wait)


def oracle_minds(
    feed: TruthFeed | None, info: EngineInfo, tracker: MindTracker
) -> Callable[[State], Mapping[str, Estimate]] | None:
    """The acting robot's source of minds (:attr:`brain.robot.RobotBrain.minds`): with a
    ``feed``, each state's tick's true minds; without, ``None`` (the tracker's estimates).

    Raises:
        OracleError: a ``feed`` and an engine that publishes no truth (its handshake lists no
            ``truth`` capability): one line saying so.
    """
    if feed is None:
        return None
    if Capability.TRUTH not in info.capabilities:
        raise OracleError(
            f"the oracle policy reads the simulated people's true minds on '{feed.key}', and engine "
            f"'{info.engine}' publishes none (no 'truth' capability in its handshake): run it against "
            "sim2d with autonomous people, or pick another policy"
        )
    model = tracker.model
    return lambda state: oracle_estimates(feed.at(state.episode, state.tick), model)
