"""A household's chain days on one engine and one brain process (``toyroom eval --days N``).

A households evaluation (:mod:`.households`) lives each chain of a household day after day,
each day's scenario made from the day before's end, so the days cannot be handed to a brain
up front as a single-day batch's episodes are (:mod:`.batches`). A :class:`DayServer` is one
engine and one brain (``python -m brain --serve``) that run the household's chain days as
they come: the evaluator writes each run's options (the very ones a brain of its own would
get: its scenario, observer, robot, policy, memory file and run-log folder) on the brain's
standard input; the brain resets the engine to the day's scenario, lives the day with a
fresh model (its memory file read at the day's start and saved at its end, as a brain of its
own would) and answers on its standard output (:data:`FINISHED`); the evaluator then scores
the day from the brain's run log and the truths it heard, as :func:`.runs.run_once` does, so
each day scores as it would alone. What the process keeps from one run to the next is its
imports, its Zenoh-free caches (the solved Q-values) and the engine.

A :class:`DayRunner` runs a household's chain days on one server (``batch``: at most that
many runs on one; 1: each day its own process pair, :func:`.episodes._run_with_retries`). A day its server did
not finish (a node that failed, a day too slow, a run that cannot be scored) is run again
alone, its own process pair with its retries, and says so in its failed attempts; the next
day starts a new server. The run-log folders keep the layout of a process pair a day
(``logs/CHAIN/<tag>.shadows``); the servers' node logs are ``logs/days.engine.log`` and
``logs/days.brain.log``, appended to by each server of the household.
"""

from __future__ import annotations

import contextlib
import json
import logging
import queue
import shutil
import subprocess
import threading
import time
import uuid
from pathlib import Path
from types import TracebackType
from typing import IO

from bridge.bridge import Bridge
from bridge.processes import engine_command, node_command, report_failure, wait_for_engine
from bridge.session import SessionSettings

from .batches import ENGINE_POLL_S, SECONDS_PER_RUN, Truths, score_served
from .episodes import _run_with_retries
from .interrupt import NODES
from .noroom import check_room
from .runs import RunResult, RunSpec, brain_command
from .truths import subscribe_truths

log = logging.getLogger("toyroom.eval")

FINISHED = "brain: finished run"
"""The brain's answer once a run is done (:data:`brain.__main__.FINISHED`; the evaluator does
not import the brain)."""
CLOSE_S = 10.0
"""How long a brain between runs gets to exit once its input is closed (then SIGTERM)."""
SERVED = "days"
"""The name of a household's servers' node logs (``days.engine.log``, ``days.brain.log``)."""


class DayServer:
    """One engine and one brain (``python -m brain --serve``) that live runs as they come,
    their node logs in ``logs``."""

    def __init__(self, first: RunSpec, logs: Path) -> None:
        self.first, self.logs = first, logs
        self.world, self.settings = f"eval-{uuid.uuid4().hex[:10]}", SessionSettings()
        self.truths = Truths()
        self.answers: queue.Queue[str] = queue.Queue()
        self.engine: subprocess.Popen[bytes] | None = None
        self.brain: subprocess.Popen[bytes] | None = None
        self.busy = False
        """Whether the brain is living a run (it ends only between runs when its input ends)."""
        self._stack = contextlib.ExitStack()

    def __enter__(self) -> DayServer:
        return self.start()

    def __exit__(
        self, kind: type[BaseException] | None, error: BaseException | None, trace: TracebackType | None
    ) -> None:
        self.close()

    def start(self) -> DayServer:
        """Start the engine (on the first run's scenario), this process's session, and the
        brain (all stopped again if one fails).

        Raises:
            RuntimeError: the engine failed.
            EvaluationStopped: a stop signal came."""
        try:
            self._start()
        except BaseException:
            self.close()
            raise
        return self

    def _start(self) -> None:
        engine_log = self.logs / f"{SERVED}.engine.log"
        scenario = str(self.first.scenario)
        command = engine_command("sim2d", self.world, self.settings, "--scenario", scenario, "--lockstep")
        self.engine = NODES.start(command, engine_log, append=True)
        bridge = self._stack.enter_context(Bridge(self.world, self.settings))
        if wait_for_engine(bridge, self.engine) is None:
            NODES.check()
            report_failure("engine", self.engine.returncode, engine_log)
            raise RuntimeError(f"{self.first.tag}: the engine failed")
        subscribe_truths(bridge, self.truths.on_truth)
        served = node_command("brain", self.world, self.settings, "--serve")
        self.brain = NODES.start(served, self.logs / f"{SERVED}.brain.log", piped=True, append=True)
        assert self.brain.stdout is not None
        reader = threading.Thread(target=_answers, args=(self.brain.stdout, self.answers), daemon=True)
        reader.start()

    def run(self, spec: RunSpec, logs: Path) -> dict[str, RunResult]:
        """Live the run of ``spec`` (its brain's run log in ``logs/<tag>.shadows``) and score it.

        Raises:
            RuntimeError, OSError, ValueError: the run did not finish, or cannot be scored (a
                node failed, the run took too long, the brain's log misses ticks).
            EvaluationStopped: a stop signal came.
        """
        brain, engine = self.brain, self.engine
        assert brain is not None and brain.stdin is not None and engine is not None
        folder = logs / f"{spec.tag}.shadows"
        shutil.rmtree(folder, ignore_errors=True)  # an earlier attempt at the day
        options = brain_command(spec, self.world, self.settings, folder)
        self.busy = True
        brain.stdin.write(json.dumps(options[options.index("brain") + 1 :]).encode() + b"\n")
        brain.stdin.flush()
        self._await(spec, brain, engine)
        self.busy = False
        NODES.check()  # stopped: what the brain left is no run
        return score_served(spec, folder, self.truths)

    def _await(self, spec: RunSpec, brain: subprocess.Popen[bytes], engine: subprocess.Popen[bytes]) -> None:
        """Wait for the brain's answer to the run of ``spec``.

        Raises:
            RuntimeError: the brain or the engine exited, or the run took too long.
            EvaluationStopped: a stop signal came."""
        deadline = time.monotonic() + SECONDS_PER_RUN
        while True:
            NODES.check()
            if engine.poll() is not None:
                raise RuntimeError(f"{spec.tag}: the engine exited")
            if time.monotonic() > deadline:
                raise RuntimeError(f"{spec.tag}: too slow (over {SECONDS_PER_RUN:g} s)")
            try:
                answer = self.answers.get(timeout=ENGINE_POLL_S)
            except queue.Empty:
                continue
            if answer.startswith(FINISHED):
                return
            if answer == "":  # the brain's output ended: it exited
                brain.wait()
                NODES.check()
                report_failure("brain", brain.returncode, self.logs / f"{SERVED}.brain.log")
                raise RuntimeError(f"{spec.tag}: the brain failed")

    def close(self) -> None:
        """Stop the brain (between runs, by closing its input: it exits) and the engine."""
        if self.brain is not None:
            if self.brain.stdin is not None:
                with contextlib.suppress(OSError):
                    self.brain.stdin.close()
            if not self.busy and not NODES.stopping:
                with contextlib.suppress(subprocess.TimeoutExpired):
                    self.brain.wait(timeout=CLOSE_S)
            NODES.stop(self.brain)
        if self.engine is not None:
            NODES.stop(self.engine)
        self._stack.close()
        self.brain = self.engine = None


def _answers(output: IO[bytes], answers: queue.Queue[str]) -> None:
    """Each line the brain writes on its standard output, then ``""`` once it is closed."""
    for line in iter(output.readline, b""):
        answers.put(line.decode(errors="replace").strip() or " ")
    answers.put("")


class DayRunner:
    """Runs a household's chain days in turn on one :class:`DayServer` (node logs in ``logs``;
    ``batch``: at most that many runs on one, ``None``: all), or (``batch`` 1) each on a
    process pair of its own, with its retries; a run its server did not finish is run alone."""

    def __init__(self, logs: Path, batch: int | None = None) -> None:
        self.logs, self.batch = logs, batch
        self.server: DayServer | None = None
        self.served = 0

    def __enter__(self) -> DayRunner:
        return self

    def __exit__(
        self, kind: type[BaseException] | None, error: BaseException | None, trace: TracebackType | None
    ) -> None:
        self.close()

    def run(
        self, spec: RunSpec, logs: Path, failed: list[str], *, alone: bool = False
    ) -> dict[str, RunResult]:
        """The run of ``spec`` scored (its logs in ``logs``; ``alone``: on a process pair of its
        own); each failed attempt told to ``failed``.

        Raises:
            RuntimeError, OSError, SubprocessError: every attempt failed.
            EvaluationStopped, OutputError: a stop signal came, or the disk is full.
        """
        if alone or (self.batch is not None and self.batch <= 1):
            return _run_with_retries(spec, logs, failed)
        if self.server is not None and self.batch is not None and self.served >= self.batch:
            self.close()
        try:
            if self.server is None:
                self.server, self.served = DayServer(spec, self.logs).start(), 0
            self.served += 1
            return self.server.run(spec, logs)
        except (RuntimeError, OSError, ValueError, subprocess.SubprocessError) as err:
            NODES.check()  # its nodes were stopped by a signal: no failure of the run
            check_room(err, logs, spec.tag)
            failed.append(f"{spec.tag}: its batch of days did not finish it ({err})")
            log.warning("%s: its batch of days did not finish it (%s): run alone", spec.tag, err)
            self.close()
        return _run_with_retries(spec, logs, failed)

    def close(self) -> None:
        """Stop the server, if one is running."""
        if self.server is not None:
            server, self.server = self.server, None
            server.close()
