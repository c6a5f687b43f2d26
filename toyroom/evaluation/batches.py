"""Several episodes' runs on one engine and one brain process per kind of run.

An evaluation episode is a few runs (the robot observing, then acting per policy), each an
engine and a brain over loopback Zenoh (:mod:`toyroom.evaluation.runs`). Starting the two
processes, importing their packages and opening their sessions cost about as much as a
short episode, so a batch shares them: one engine for all of the batch's runs, and for
each kind of run one brain that runs it on every episode in turn (``python -m brain
--episodes``), resetting the engine to each scenario. Every run still begins with a fresh
model and a fresh episode (the engine's reset reloads the scenario and reseeds it, so the
episode is the one a fresh engine plays), so each run scores as it would alone.

The evaluator tells the episodes' truths apart by their episode number (the engine counts
its resets) and reads each run's scene from the brain's run log. A run whose brain failed
or stopped early is absent from the result: its episode is for the caller to run again,
alone (:func:`toyroom.evaluation.episodes.run_episodes`).
"""

from __future__ import annotations

import logging
import subprocess
import threading
import time
import uuid
from collections.abc import Iterable, Sequence
from dataclasses import dataclass
from pathlib import Path

from bridge.bridge import Bridge
from bridge.processes import engine_command, report_failure, wait_for_engine
from bridge.pubsub import Received
from bridge.session import SessionSettings
from protocol import Truth

from .interrupt import NODES
from .runs import RunRecord, RunResult, RunSpec, brain_command, read_log, score_run, settle
from .truths import subscribe_truths

log = logging.getLogger("toyroom.eval")

SECONDS_PER_RUN = 900.0
"""How long one run of a batch may take before its brain is stopped."""
ENGINE_POLL_S = 0.5
"""How often a batch looks whether its engine is still there while a brain runs."""


class Truths:
    """Every truth the engine published, by (episode, tick)."""

    def __init__(self) -> None:
        self.heard: dict[tuple[int, int], Truth] = {}
        self.lock = threading.Lock()

    def on_truth(self, truth: Truth, _: Received) -> None:
        with self.lock:
            self.heard[(truth.episode, truth.tick)] = truth

    def take(self, episode: int) -> dict[int, Truth]:
        """One episode's truths by tick, forgotten here (each episode is one run's)."""
        with self.lock:
            ours = [key for key in self.heard if key[0] == episode]
            return {tick: self.heard.pop((e, tick)) for e, tick in ours}


@dataclass
class BatchResult:
    """What a batch measured: per episode, its runs' scores in order (``None`` where any of
    them did not finish), and per kind of run, its mean seconds per episode."""

    scores: list[list[dict[str, RunResult]] | None]
    seconds: list[float]

    @classmethod
    def nothing(cls, episodes: int, kinds: int) -> BatchResult:
        """A batch that finished no episode (its engine failed)."""
        return cls([None] * episodes, [0.0] * kinds)


def run_batch(episodes: Sequence[Sequence[RunSpec]], logs: Path) -> BatchResult:
    """Each episode's runs (``episodes[i][k]``: the k-th kind of run of episode i; the same
    kinds, in the same order, for every episode, and no engine options of their own) on one
    engine, with one brain per kind (a failed brain's log is kept in ``logs``)."""
    scenarios = [runs[0].scenario for runs in episodes]
    name = f"batch-{scenarios[0].stem}-{uuid.uuid4().hex[:6]}"
    world, settings = f"eval-{uuid.uuid4().hex[:10]}", SessionSettings()
    engine_log = logs / f"{name}.engine.log"
    engine = NODES.start(
        engine_command("sim2d", world, settings, "--scenario", str(scenarios[0]), "--lockstep"), engine_log
    )
    result = BatchResult([[] for _ in episodes], [])
    truths = Truths()
    try:
        with Bridge(world, settings) as bridge:
            if wait_for_engine(bridge, engine) is None:
                NODES.check()
                report_failure("engine", engine.returncode, engine_log)
                return BatchResult.nothing(len(episodes), len(episodes[0]))
            subscribe_truths(bridge, truths.on_truth)
            for kind in range(len(episodes[0])):
                if engine.poll() is not None:  # gone: no later run can finish
                    NODES.check()
                    report_failure("engine", engine.returncode, engine_log)
                    return BatchResult.nothing(len(episodes), len(episodes[0]))
                specs = [runs[kind] for runs in episodes]
                folder = logs / f"{name}-{specs[0].tag.removeprefix(f'{scenarios[0].stem}-')}"
                started = time.monotonic()
                finished = _run_kind(specs, world, settings, folder, engine)
                result.seconds.append((time.monotonic() - started) / len(specs))
                for i, spec in enumerate(specs):
                    NODES.check()  # stopped: no more scoring (seconds a run, under load)
                    scored = _scored(spec, folder / spec.scenario.stem, truths) if i < finished else None
                    current = result.scores[i]
                    if scored is None or current is None:
                        result.scores[i] = None
                    else:
                        current.append(scored)
    finally:
        NODES.stop(engine)
    return result


def _run_kind(
    specs: Sequence[RunSpec],
    world: str,
    settings: SessionSettings,
    folder: Path,
    engine: subprocess.Popen[bytes],
) -> int:
    """One brain running ``specs`` (one kind of run, one per episode) in turn; how many of
    them it finished (all, or those before the episode it failed on). A brain whose engine
    exited is stopped (it would wait for the engine to come back)."""
    command = brain_command(specs[0], world, settings, folder, [s.scenario for s in specs])
    brain_log = folder.with_name(folder.name + ".brain.log")
    brain = NODES.start(command, brain_log)
    deadline = time.monotonic() + SECONDS_PER_RUN * len(specs)
    code = None
    while code is None and time.monotonic() < deadline and engine.poll() is None:
        try:
            code = brain.wait(timeout=ENGINE_POLL_S)
        except subprocess.TimeoutExpired:
            continue
    if code is None:
        log.warning(
            "stopping the brain of %s: %s",
            folder.name,
            "its engine exited" if engine.poll() is not None else "too slow",
        )
        NODES.stop(brain)
    NODES.check()  # stopped: what the brain left is no run
    if code == 0:
        return len(specs)
    report_failure("brain", brain.returncode, brain_log)
    begun = sum(1 for s in specs if (folder / s.scenario.stem / "inputs.jsonl").exists())
    return max(0, begun - 1)  # the last one begun is the one it failed on


def _scored(spec: RunSpec, directory: Path, truths: Truths) -> dict[str, RunResult] | None:
    """:func:`score_served`, or ``None`` (with a warning) if the run cannot be scored."""
    try:
        return score_served(spec, directory, truths)
    except (RuntimeError, OSError, ValueError) as err:
        log.warning("batch run %s cannot be scored: %s", spec.tag, err)
        return None


def _missing(truths: Truths, episode: int, ticks: Iterable[int]) -> list[int]:
    """The ``ticks`` of ``episode`` whose truth has not been heard, in order."""
    with truths.lock:
        return sorted(tick for tick in ticks if (episode, tick) not in truths.heard)


def score_served(spec: RunSpec, directory: Path, truths: Truths) -> dict[str, RunResult]:
    """A finished run's scores, from its log in ``directory`` and the truths of its episode
    (a run of a brain that serves several episodes, :mod:`.dayserver` too): every tick the
    brain handled must have its truth (one lost, the run is no run: it is run again alone).

    Raises:
        RuntimeError, OSError, ValueError: it cannot be scored (an engine that went away
            mid-run, a mind missing).
    """
    record = RunRecord()
    read_log(record, directory, spec.observer)
    episodes = {s.episode for s in record.states.values()}
    if record.info is None:
        raise RuntimeError("its log holds no engine handshake")
    if len(episodes) != 1:
        raise RuntimeError(f"its log holds {len(episodes)} episodes (the engine went away mid-run)")
    (episode,) = episodes
    final = max(record.states)
    # the engine publishes a tick's truth before it answers the step: once the last is
    # here, every earlier one is (one publisher, in order)
    if (episode, final) not in truths.heard:
        settle(lambda: 0, done=lambda: (episode, final) in truths.heard, quiet=0.0)
    if (episode, final) not in truths.heard:
        raise RuntimeError(f"the truth of its last tick ({final}) never arrived")
    if _missing(truths, episode, record.states):  # a link lost under load: wait a little
        settle(lambda: 0, done=lambda: not _missing(truths, episode, record.states), quiet=0.0, limit=5.0)
    if missing := _missing(truths, episode, record.states):
        shown = ", ".join(map(str, missing[:5])) + (", ..." if len(missing) > 5 else "")
        raise RuntimeError(
            f"the truths of {len(missing)} of its {len(record.states)} ticks never arrived ({shown})"
        )
    record.truths = truths.take(episode)
    return score_run(spec, record.info.scene, record, directory)
