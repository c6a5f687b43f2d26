"""One evaluation run: an engine and a brain process on a private loopback world, in
lock-step, with the evaluator listening to ``engine/truth`` (the people's true minds, which
only the evaluator reads); then the brain's minds scored against the truth, tick by tick,
with the states, events and minds read from the brain's run log (:mod:`brain.outputs.runlog`:
the live observer's and each shadow's minds, and what the brain handled) instead of heard
on the wire, a message a tick to the evaluator instead of four."""

from __future__ import annotations

import threading
import time
import uuid
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path

from bridge.bridge import Bridge
from bridge.processes import engine_command, node_command, report_failure, wait_for_engine
from bridge.pubsub import Received
from bridge.session import SessionSettings
from protocol import (
    EngineInfo,
    Event,
    EventKind,
    Mind,
    Morning,
    Perception,
    Policy,
    RobotMode,
    Scene,
    State,
    Truth,
    decode,
    morning_of,
)

from .helpfulness import PersonHelp, helpfulness
from .heuristic import MotionHeuristic
from .interrupt import NODES
from .metrics import Counts, EpisodeOutcome, false_belief_causes, score_tick
from .nestedscore import score_nested
from .outcome import judge
from .revealed import Stretch, detection_lead, detection_lead_any, knowable, stretches
from .robottasks import TaskTally, task_tally
from .scoredminds import ScoredMind, read_scored_minds
from .truths import subscribe_truths
from .wantread import score_want, want_stretches

MOTION = "motion"
LOST_TIMEOUT_S = 60.0
"""How long a run's brain waits for a lost engine to come back (``python -m brain
--lost-timeout``) before the run fails and is run again: a peer link that dropped under load
while a third session (the evaluator's) held the world port was seen never to come back, both
nodes alive and idle, the brain waiting for good (2026-12-07, seed 202, load 13)."""
"""The motion-heuristic observer's name (:mod:`toyroom.evaluation.heuristic`)."""


@dataclass(frozen=True)
class RunSpec:
    """One run of one episode."""

    scenario: Path
    observer: str
    robot: RobotMode
    timeout: float = 30.0
    shadows: tuple[str, ...] = ()
    """Observers the same brain runs alongside on the same ticks (``python -m brain --shadow``)."""
    brain_args: tuple[str, ...] = ()
    """More options for the brain, e.g. ``("--set", "belief_model=graded")``."""
    policy: Policy = Policy.TOM
    """The acting robot's policy (``RobotSettings.policy``)."""
    perception: Perception = Perception.OMNISCIENT
    """What the robot sees (the brain is told by ``brain_args``): the motion heuristic then
    knows no more of the world than the robot does."""
    engine_args: tuple[str, ...] = ()
    """More options for the engine, e.g. ``("--policy", "policy.npz")``."""

    @property
    def tag(self) -> str:
        """``<episode>-<observer>-observe`` or ``<episode>-<observer>-act-<policy>``: its logs' names."""
        action = self.robot if self.robot == RobotMode.OBSERVE else f"{self.robot}-{self.policy}"
        return f"{self.scenario.stem}-{self.observer}-{action}"


@dataclass
class RunResult:
    """What one run of an episode gave: its counts, outcome, ticks, help per person and tasks."""

    counts: Counts = field(default_factory=Counts)
    outcome: EpisodeOutcome = field(default_factory=EpisodeOutcome)
    ticks: int = 0
    help: dict[str, PersonHelp] = field(default_factory=dict)
    """Per person, how much the robot helped (:mod:`toyroom.evaluation.helpfulness`)."""
    tasks: TaskTally = TaskTally()
    """The acting robot's tasks, begun and finished or not (:mod:`toyroom.evaluation.robottasks`)."""
    morning: Morning | None = None
    """Where the run's last truth left things (the next day of a household starts there)."""


@dataclass
class RunRecord:
    """What the evaluator knows of a run: the truth it hears (a channel that is never
    dropped), and the states, events and minds of the brain's run log."""

    minds: dict[int, Mind | ScoredMind] = field(default_factory=dict)
    truths: dict[int, Truth] = field(default_factory=dict)
    states: dict[int, State] = field(default_factory=dict)
    took: dict[int, set[str]] = field(default_factory=dict)
    """Tick -> the people who took an item then."""
    takes: list[tuple[int, str, str]] = field(default_factory=list)
    """(tick, person, item) of every take, in order."""
    playing: dict[str, str | None] = field(default_factory=dict)
    regions: dict[str, str] = field(default_factory=dict)
    reached: list[tuple[int, str, str]] = field(default_factory=list)
    """(tick, person, item played with or region entered), in order: when goals were met."""
    events: list[Event] = field(default_factory=list)
    info: EngineInfo | None = None
    """The engine's handshake, as the brain logged it (its scene)."""
    lock: threading.Lock = field(default_factory=threading.Lock)

    def on_truth(self, truth: Truth, _: Received) -> None:
        with self.lock:
            self.truths[truth.tick] = truth

    def on_event(self, event: Event, _: Received | None = None) -> None:
        """Who took what, who plays with what, who is where."""
        with self.lock:
            self.events.append(event)
            if event.kind is EventKind.TAKE:
                self.took.setdefault(event.tick, set()).add(event.actor)
                self.takes.append((event.tick, event.actor, event.item or ""))
            elif event.kind is EventKind.PLAY:
                self.playing[event.actor] = event.item
                self.reached.append((event.tick, event.actor, event.item or ""))
            elif event.kind in (EventKind.STOP, EventKind.DROP):
                self.playing[event.actor] = None
            elif event.kind is EventKind.GIVE:
                self.playing[event.actor] = None
                if event.target is not None:
                    self.playing[event.target] = None
            elif event.kind is EventKind.ENTER and event.location is not None:
                self.regions[event.actor] = event.location
                self.reached.append((event.tick, event.actor, event.location))


def read_log(record: RunRecord, directory: Path, observer: str) -> None:
    """Fill ``record`` from a brain's run log (:mod:`brain.outputs.runlog`): the engine's
    handshake, the states and events it handled, and ``observer``'s minds."""
    for line in (directory / "inputs.jsonl").read_bytes().splitlines():
        message = decode(line)
        if isinstance(message, State):
            record.states[message.tick] = message
        elif isinstance(message, Event):
            record.on_event(message)
        elif isinstance(message, EngineInfo):
            record.info = message
    record.minds.update(read_minds(directory, observer))


def read_minds(directory: Path, observer: str) -> dict[int, ScoredMind]:
    """What is scored of ``observer``'s minds, by tick, from its ``minds-<observer>.jsonl`` in
    ``directory`` (:mod:`toyroom.evaluation.scoredminds`)."""
    return read_scored_minds(directory / f"minds-{observer}.jsonl")


def brain_command(
    spec: RunSpec, world: str, settings: SessionSettings, shadow_dir: Path, episodes: Sequence[Path] = ()
) -> list[str]:
    """The brain process of a run, logging what it handled and inferred into ``shadow_dir``
    (with its shadow observers' minds); with ``episodes``, the same run of each of those
    scenarios in turn, each logged into ``shadow_dir/<its stem>``."""
    shadows = [a for o in spec.shadows for a in ("--shadow", o)]
    shadows += ["--shadow-out", str(shadow_dir), "--run-log", str(shadow_dir)]
    chosen = ("--episodes", *map(str, episodes)) if episodes else ("--scenario", str(spec.scenario))
    return node_command(
        "brain",
        world,
        settings,
        *chosen,
        *("--observer", spec.observer, "--robot", spec.robot),
        *("--timeout", str(spec.timeout), "--lost-timeout", str(LOST_TIMEOUT_S), "--log-level", "WARNING"),
        *shadows,
        *spec.brain_args,
        *(("--set", f"policy={spec.policy}") if spec.robot == RobotMode.ACT else ()),
    )


def run_once(spec: RunSpec, logs: Path) -> dict[str, RunResult]:
    """Run an engine and a brain on ``spec`` and score the brain's minds against the truth:
    the live observer's and each shadow's, from the brain's run log.

    Raises:
        RuntimeError: when a node process fails (its log, in ``logs``, says why).
    """
    world = f"eval-{uuid.uuid4().hex[:10]}"
    settings = SessionSettings()
    tag = spec.tag
    engine_log, brain_log = logs / f"{tag}.engine.log", logs / f"{tag}.brain.log"
    shadow_dir = logs / f"{tag}.shadows"
    engine = NODES.start(
        engine_command(
            "sim2d", world, settings, "--scenario", str(spec.scenario), "--lockstep", *spec.engine_args
        ),
        engine_log,
    )
    brain = None
    record = RunRecord()
    try:
        with Bridge(world, settings) as bridge:
            info = wait_for_engine(bridge, engine)
            if info is None:
                NODES.check()
                report_failure("engine", engine.returncode, engine_log)
                raise RuntimeError(f"{tag}: the engine failed")
            subscribe_truths(bridge, record.on_truth)
            brain = NODES.start(brain_command(spec, world, settings, shadow_dir), brain_log)
            code = brain.wait(timeout=1800)
            NODES.check()  # stopped: its nodes were, so what they left is no run
            if code != 0:
                report_failure("brain", brain.returncode, brain_log)
                raise RuntimeError(f"{tag}: the brain failed")
            read_log(record, shadow_dir, spec.observer)  # the brain's own record of the run
            final = max(record.states, default=0)
            settle(lambda: len(record.truths), done=lambda: max(record.truths, default=-1) >= final)
    finally:
        for process in (brain, engine):
            if process is not None:
                NODES.stop(process)
    return score_run(spec, info.scene, record, shadow_dir)


def score_run(spec: RunSpec, scene: Scene, record: RunRecord, shadow_dir: Path) -> dict[str, RunResult]:
    """Every observer's scores of a run of ``spec`` on ``scene``: the live one's from
    ``record``, each shadow's from its file in ``shadow_dir``, and (observing) the motion
    heuristic's.

    Raises:
        RuntimeError: an observer's minds miss ticks of the truth.
    """
    tag = spec.tag
    outcome = EpisodeOutcome()
    if record.truths:
        last = record.truths[max(record.truths)]
        outcome = judge(scene, last, record.playing, record.regions, record.reached)
    check_complete(tag, spec.observer, record.minds, record.truths)
    cells = {
        tick: {body.id: (body.cell.col, body.cell.row) for body in state.agents}
        for tick, state in record.states.items()
    }
    spots = {loc.id: (loc.cell.col, loc.cell.row) for loc in scene.locations}
    truth = TruthView(record.truths, record.took, stretches(record.truths, cells, spots), record.takes)
    results = {spec.observer: _score(record.minds, truth, outcome)}
    results[spec.observer].help = helpfulness(scene, record.states, record.truths, record.events)
    results[spec.observer].tasks = task_tally(record.minds)
    if record.truths:
        results[spec.observer].morning = morning_of(record.truths[max(record.truths)])
    if spec.robot == RobotMode.OBSERVE:
        heuristic = MotionHeuristic(scene, embodied=spec.perception == Perception.EMBODIED)
        guessed = {
            tick: heuristic.mind(record.states[tick], record.truths[tick])
            for tick in sorted(record.states)
            if tick in record.truths
        }
        results[MOTION] = _score(guessed, truth, outcome)
    for observer in spec.shadows:
        NODES.check()  # stopped: no more scoring
        shadow = read_minds(shadow_dir, observer)
        check_complete(tag, observer, shadow, record.truths)
        results[observer] = _score(shadow, truth, outcome)
    return results


def missing_ticks(minds: Mapping[int, Mind | ScoredMind], truths: Mapping[int, Truth]) -> list[int]:
    """The ticks of the truth that no mind was heard for, in order."""
    return sorted(set(truths) - set(minds))


def check_complete(
    tag: str, observer: str, minds: Mapping[int, Mind | ScoredMind], truths: Mapping[int, Truth]
) -> None:
    """Raise when an observer's minds miss ticks of the truth: a mind lost on the way (say,
    published before the evaluator's session was connected) would silently drop a tick
    from the scores, so the run fails instead and is tried again (it is deterministic)."""
    missing = missing_ticks(minds, truths)
    if missing:
        shown = ", ".join(map(str, missing[:5])) + (", ..." if len(missing) > 5 else "")
        raise RuntimeError(
            f"{tag}: {observer}'s minds of {len(missing)} of {len(truths)} ticks never arrived "
            f"(ticks {shown})"
        )


class TruthView:
    """What every observer of a run is scored against: the truth by tick, who took an item
    when, the revealed stretches, and per tick the false beliefs' causes, which of them
    the robot could know of (:mod:`toyroom.evaluation.revealed`) and who is in a want
    stretch (:mod:`toyroom.evaluation.wantread`)."""

    def __init__(
        self,
        truths: dict[int, Truth],
        took: dict[int, set[str]],
        found: list[Stretch],
        takes: Sequence[tuple[int, str, str]] = (),
    ) -> None:
        self.truths, self.took, self.stretches = truths, took, found
        self.causes = false_belief_causes(truths)
        self.known = knowable(truths, self.causes, found)
        self.wanting = want_stretches(truths, takes)


def _score(minds: Mapping[int, Mind | ScoredMind], truth: TruthView, outcome: EpisodeOutcome) -> RunResult:
    """Score every tick that has both a mind and the truth (channels that are never dropped),
    and every revealed stretch."""
    result = RunResult(outcome=outcome)
    seen: set[str] = set()
    last: tuple[tuple[object, ...], Counts] | None = None
    for tick in sorted(truth.truths):
        seen |= {p for t, people in truth.took.items() if t <= tick for p in people}
        if tick not in minds:
            continue
        now = truth.truths[tick]
        # what a tick's counts depend on: most ticks it is the tick before's, to the value
        causes, known, wanting = truth.causes[tick], truth.known[tick], truth.wanting[tick]
        inputs = (minds[tick].agents, now.agents, now.items, frozenset(seen), causes, known, wanting)
        if last is not None and last[0] == inputs:
            counts = last[1]
        else:
            where = {place.item: place.location for place in now.items}
            counts = score_tick(minds[tick], now, where, seen, causes, known)
            score_nested(minds[tick], now, counts)
            counts.add_want(score_want(minds[tick], now, wanting))
            last = (inputs, counts)
        result.counts.add(counts)
        result.ticks += 1
    for stretch in truth.stretches:
        lead = detection_lead(minds, stretch)
        result.counts.stretches += 1
        if lead is not None:
            result.counts.detected += 1
            result.counts.leads.append(lead)
        lead = detection_lead_any(minds, stretch, truth.truths)
        if lead is not None:
            result.counts.detected_any += 1
            result.counts.leads_any.append(lead)
    return result


def settle(
    count: Callable[[], int], done: Callable[[], bool], quiet: float = 0.3, limit: float = 15.0
) -> None:
    """Wait until the last messages have arrived: ``done()`` and ``count()`` (of the messages
    heard) unchanged for ``quiet`` s."""
    deadline = time.monotonic() + limit
    seen, since = count(), time.monotonic()
    while time.monotonic() < deadline:
        time.sleep(0.05)
        NODES.check()
        now = count()
        if now != seen:
            seen, since = now, time.monotonic()
        elif done() and time.monotonic() - since >= quiet:
            return
