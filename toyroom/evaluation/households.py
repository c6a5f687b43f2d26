"""``toyroom eval --days N``: households lived over days, the brain with a memory of each person.

Episode ``i`` of a sweep becomes a household of ``N`` days (:mod:`sim2d.generation.households`):
day 1 is the episode itself, and each later day starts where the day before ended in *that
run*, so every run is a chain of days of its own (:class:`DayChain`):

- ``observe``: the BToM brain observing, with its memory file (``--memory``), the baselines
  (``truebelief``, ``perceptonly``) as its shadows and the motion heuristic scored on the same
  ticks; the robot changes nothing, so this chain is the household without a robot (``none``);
- ``observe-fresh``: the BToM brain observing the very same days with no memory: a first-day
  brain on every day (its scores under ``btom-fresh``);
- one chain per acting policy, each with its own memory file (``robot-<policy>``);
- ``tom-fresh``: the ``tom`` robot with no memory, every day a first day (``robot-tom-fresh``).

Each day of a household is one :class:`~.records.EpisodeRecord` (its ``day`` set) holding every
chain's run of that day, so the numbers of a day are paired on the same people, as an
episode's are (:mod:`.aggregate`); they are reported per day and pooled over days 3 on.
"""

from __future__ import annotations

import json
import logging
import shutil
import time
import tomllib
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import msgspec

from bridge.recording.atomic import write_text
from protocol import MAX_TICKS, Morning, Observer, Policy, RobotMode

from .chaindays import ChainDay, line_of, prune_work, read_days
from .conditions import Condition
from .days import day_metrics, days_report
from .dayserver import DayRunner
from .episodes import BRAIN_OBSERVERS, _recorded
from .generation import generate_day, map_of
from .interrupt import NODES, EvaluationStopped
from .pool import run_chunks
from .records import FRESH, EpisodeRecord, RunKey, RunScores
from .resume import EPISODES, Ledger, finished, plan_of, start
from .runs import RunResult, RunSpec
from .summary import HouseholdEvaluation
from .timing import cpu_seconds

log = logging.getLogger("toyroom.eval")

BTOM = Observer.BTOM.value
"""The observer every chain's brain runs (its baselines are the observing chain's shadows)."""


@dataclass(frozen=True)
class DayChain:
    """One run of every day of a household."""

    name: str
    robot: RobotMode
    policy: Policy = Policy.TOM
    memory: bool = True
    follows: str | None = None
    """Run on the days of this other chain (an observer, which changes nothing) instead of its own."""

    def key(self, observer: str) -> str:
        """The key a run's scores for ``observer`` go under in a day's record."""
        if self.robot == RobotMode.ACT:
            return str(RunKey.acting(self.policy, fresh=not self.memory))
        return str(RunKey(observer, fresh=not self.memory))


def chains(policies: Sequence[Policy]) -> list[DayChain]:
    """The chains of a household (the module's docstring), observers first."""
    return [
        DayChain(RobotMode.OBSERVE, RobotMode.OBSERVE),
        DayChain(f"{RobotMode.OBSERVE}-{FRESH}", RobotMode.OBSERVE, memory=False, follows=RobotMode.OBSERVE),
        *(DayChain(policy, RobotMode.ACT, policy) for policy in policies),
        *([DayChain(f"{Policy.TOM}-{FRESH}", RobotMode.ACT, memory=False)] if Policy.TOM in policies else []),
    ]


WORK = "work"
"""The scratch folder in the output folder: each household's scenarios, mornings, memory files
and run logs (:mod:`.chaindays`)."""


@dataclass(frozen=True)
class HouseholdJob:
    """Household ``index`` of a sweep with ``seed`` under ``condition``, lived ``days`` days."""

    index: int
    seed: int
    workdir: str
    days: int
    condition: Condition = Condition()
    brain_args: tuple[str, ...] = ()
    policies: tuple[Policy, ...] = (Policy.TOM,)
    max_ticks: int = MAX_TICKS
    record: bool = False
    batch: int | None = None
    """At most this many runs (chain days) of the household share one engine and one brain
    (``None``: all of them; 1: a process pair a run; :mod:`.dayserver`)."""


class ChainFailed(RuntimeError):
    """A chain's day that failed in an earlier session of the evaluation (:mod:`.chaindays`)."""


Keep = Callable[[ChainDay], None]
"""Told of each chain day as it finishes (:mod:`.chaindays`)."""


def run_household(
    job: HouseholdJob, kept: Mapping[tuple[str, int], ChainDay] | None = None, keep: Keep | None = None
) -> list[EpisodeRecord]:
    """Every day of the household, one record each (a day whose runs kept failing comes back
    with its ``error``, as do the days after it in the chains that failed). ``kept``: the chain
    days an earlier session finished, by (chain, day), taken as they are; ``keep`` is told of
    each chain day this one finishes.

    Raises:
        EvaluationStopped: a stop signal came (:mod:`.interrupt`).
    """
    started = time.monotonic()
    home = Path(job.workdir) / job.condition.name / f"household-{job.index}"
    lived = _Lived(job, home, dict(kept or {}), keep or (lambda entry: None))
    (home / "logs").mkdir(parents=True, exist_ok=True)
    with DayRunner(home / "logs", job.batch) as runner:
        for chain in chains(job.policies):
            try:
                lived.scenarios[chain.name] = _live(lived, chain, runner)
            except EvaluationStopped:
                raise
            except Exception as err:  # a chain that fails stops there; the others go on
                NODES.check()  # a run stopped by a signal is no failure of the chain
                _failed(lived, chain, err)
    took = (time.monotonic() - started) / job.days
    first_error = min(lived.errors, default=job.days + 1)
    observed = lived.scenarios.get(RobotMode.OBSERVE, {})  # the observing chain's days
    return [
        EpisodeRecord(
            index=job.index,
            map=map_of(job.index),
            scenario=observed.get(day, Path(f"household-{job.index}-d{day}")).stem,
            run_seconds=lived.seconds[day] if day < first_error else None,
            runs=lived.runs[day] if day < first_error else {},
            error=lived.errors.get(day)
            or (f"an earlier day failed (day {first_error})" if day > first_error else None),
            failed_runs=lived.failures[day] or None,
            seconds=took if day < first_error else None,
            day=day,
        )
        for day in range(1, job.days + 1)
    ]


def _failed(lived: _Lived, chain: DayChain, err: Exception) -> None:
    """``chain`` stopped on its first day not lived, for ``err``: the day's error, kept."""
    day = 1 + len([d for d in lived.runs if chain.key(BTOM) in lived.runs[d]])
    reason = str(err) if isinstance(err, ChainFailed) else f"{type(err).__name__}: {err}"
    lived.errors.setdefault(day, f"{chain.name}, day {day}: {reason}")
    log.error("household %d: %s", lived.job.index, lived.errors[day])
    if not isinstance(err, ChainFailed):
        lived.keep(lived.entry(chain, day, Path(), error=reason))


@dataclass
class _Lived:
    """What the chains of a household have lived so far, day by day."""

    job: HouseholdJob
    home: Path
    kept: dict[tuple[str, int], ChainDay]
    keep: Keep
    runs: dict[int, dict[str, RunScores]] = field(default_factory=dict)
    seconds: dict[int, dict[str, float]] = field(default_factory=dict)
    scenarios: dict[str, dict[int, Path]] = field(default_factory=dict)
    failures: dict[int, list[str]] = field(default_factory=dict)
    errors: dict[int, str] = field(default_factory=dict)

    def __post_init__(self) -> None:
        for day in range(1, self.job.days + 1):
            self.runs[day], self.seconds[day], self.failures[day] = {}, {}, []

    def entry(self, chain: DayChain, day: int, scenario: Path, **more: Any) -> ChainDay:
        """The record of ``chain``'s ``day`` (paths relative to the scratch folder)."""
        work = Path(self.job.workdir)
        where = scenario.relative_to(work).as_posix() if scenario.is_relative_to(work) else ""
        name = self.job.condition.name
        return ChainDay(
            condition=name, household=self.job.index, chain=chain.name, day=day, scenario=where, **more
        )

    def restore(self, chain: DayChain, entry: ChainDay) -> tuple[Path, Path | None]:
        """Take an earlier session's ``entry`` of ``chain`` as this day's; its scenario and
        next morning (absolute).

        Raises:
            ChainFailed: the chain failed on that day."""
        if entry.error is not None:
            raise ChainFailed(entry.error)
        work = Path(self.job.workdir)
        self.runs[entry.day] |= entry.runs
        self.seconds[entry.day][chain.name] = entry.seconds
        self.failures[entry.day] += entry.failed_runs
        return work / entry.scenario, None if entry.morning is None else work / entry.morning


def _live(lived: _Lived, chain: DayChain, runner: DayRunner) -> dict[int, Path]:
    """Run ``chain`` through every day (those finished in an earlier session taken as they
    are, :mod:`.chaindays`) by ``runner`` (:mod:`.dayserver`; a recorded run has a process
    pair of its own), each told to ``lived.keep``; its scenarios by day."""
    job, home = lived.job, lived.home
    days: dict[int, Path] = {}
    morning: Path | None = None
    memory = home / "memory" / f"{chain.name}.sqlite"
    memory.parent.mkdir(parents=True, exist_ok=True)
    logs = home / "logs" / chain.name
    logs.mkdir(parents=True, exist_ok=True)

    def run(spec: RunSpec, failed: list[str]) -> dict[str, RunResult]:
        return runner.run(spec, logs, failed, alone=job.record)

    for day in range(1, job.days + 1):
        if (chain.name, day) in lived.kept:
            days[day], morning = lived.restore(chain, lived.kept[(chain.name, day)])
            continue
        if chain.follows is not None:
            scenario = lived.scenarios[chain.follows][day]
        else:
            drawn = job.condition.spec(job.max_ticks)
            place = home / "scenarios" / chain.name
            scenario = generate_day(place, job.index, job.seed, drawn, day, morning)
        days[day] = scenario
        morning = _live_day(lived, chain, day, scenario, run, morning)
    return days


def _live_day(
    lived: _Lived,
    chain: DayChain,
    day: int,
    scenario: Path,
    run: Callable[[RunSpec, list[str]], dict[str, RunResult]],
    morning: Path | None,
) -> Path | None:
    """Live ``chain``'s ``day`` on ``scenario`` by ``run`` (its failed attempts told to the
    list it is given), keep it (``lived.keep``), and return the next day's morning (``morning``
    as it was when the day left none)."""
    job, home = lived.job, lived.home
    spec = _spec(job, chain, scenario, home / "memory" / f"{chain.name}.sqlite")
    began = time.monotonic()
    failed: list[str] = []
    try:
        result = run(spec, failed)
    finally:
        lived.failures[day] += failed
    took = time.monotonic() - began
    lived.seconds[day][chain.name] = took
    scores = {chain.key(observer): RunScores.of(scored) for observer, scored in result.items()}
    lived.runs[day] |= scores
    live = result[spec.observer].morning
    if live is None and day < job.days:
        raise RuntimeError(f"day {day} left no truth to start day {day + 1} from")
    if live is not None:
        named = {
            "household": tomllib.loads(scenario.read_text())["household"]["id"],
            "map": map_of(job.index),
        }
        morning = home / "mornings" / chain.name / f"day{day}.json"
        morning.parent.mkdir(parents=True, exist_ok=True)
        morning.write_bytes(msgspec.json.encode(msgspec.structs.replace(live, **named)))
    next_morning = None if morning is None else morning.relative_to(job.workdir).as_posix()
    NODES.check()  # a day that came back after a stop signal is not kept
    done = {"runs": scores, "seconds": took, "failed_runs": failed, "morning": next_morning}
    lived.keep(lived.entry(chain, day, scenario, **done))
    return morning


def _spec(job: HouseholdJob, chain: DayChain, scenario: Path, memory: Path) -> RunSpec:
    """The run of ``chain`` on ``scenario``: an observer with the baselines as shadows (the
    chain with memory), or the robot acting by the chain's policy."""
    values = ("--values-cache", str(Path(job.workdir) / "values"))
    remember = ("--memory", str(memory)) if chain.memory else ()
    args = (*job.condition.brain_args(), *job.brain_args, *values, *remember)
    shadows = tuple(BRAIN_OBSERVERS[1:]) if chain.robot == RobotMode.OBSERVE and chain.memory else ()
    spec = RunSpec(
        scenario,
        BTOM,
        chain.robot,
        shadows=shadows,
        brain_args=args,
        policy=chain.policy,
        perception=job.condition.perception,
    )
    if job.record:
        spec = _recorded(spec, Path(job.workdir).parent / "recordings" / job.condition.name / chain.name)
    return spec


def morning_file(path: Path) -> Morning:
    """A chain's saved morning (for tests and reports)."""
    return msgspec.json.decode(path.read_bytes(), type=Morning)


def evaluate_households(
    households: int,
    seed: int,
    out: Path,
    days: int,
    *,
    conditions: Sequence[Condition] = (Condition(),),
    workers: int = 2,
    brain_args: tuple[str, ...] = (),
    command: str = "",
    policies: Sequence[Policy] = (Policy.TOM,),
    record: bool = False,
    max_ticks: int = MAX_TICKS,
    progress: Callable[[float], None] | None = None,
    fresh: bool = False,
    notify: Callable[[str], None] | None = None,
    backend: str = "local",
    address: str | None = None,
    batch: int | None = None,
) -> HouseholdEvaluation:
    """Live ``households`` households of every condition for ``days`` days each and write
    ``metrics.json`` (per condition: ``by_day`` and ``later``, :mod:`.days`), ``episodes.json``
    (every day's record), ``report.md`` (the table by day) and ``days-<condition>.png``
    (help by day) into ``out``; the scratch folder ``out/work`` is then pruned
    (:func:`.chaindays.prune_work`). ``progress`` is told of the household days done, a
    chain's day at a time (a fraction of one). An unfinished evaluation of the same plan in
    ``out`` is resumed from its finished chain days (:mod:`.chaindays`; ``notify`` is told how
    many), unless ``fresh``. ``backend`` ``ray``: each household a Ray task, on the cluster at
    ``address`` (:mod:`.rayhouseholds`). ``batch``: at most this many runs of a household
    (its chains' days) share one engine and one brain process (``None``: all of them; 1: each
    its own pair; :mod:`.dayserver`).

    Raises:
        IncompatibleRun: ``out`` holds an unfinished evaluation of another plan.
        EvaluationStopped: a stop signal came (:mod:`.interrupt`); the finished days are kept.
    """
    out.mkdir(parents=True, exist_ok=True)
    NODES.reset()
    plan = plan_of(households, seed, conditions, brain_args, policies, record, max_ticks, days)
    state, resumed = start(out, plan, fresh, WORK)
    names = [c.name for c in conditions]
    kept = read_days(out / EPISODES, names, households, days) if resumed else {}
    workdir = out / state.workdir
    per_day = len(chains(policies))
    total = households * len(conditions) * days * per_day
    already = sum(len(found) for found in kept.values())
    if already and notify is not None:
        notify(f"resuming the unfinished evaluation in {out}: {already} of {total} chain days kept")
    if already and progress is not None:
        progress(already / per_day)
    ledger = Ledger(out, state, cpu_seconds)
    jobs = [
        HouseholdJob(i, seed, str(workdir), days, c, brain_args, tuple(policies), max_ticks, record, batch)
        for c in conditions
        for i in range(households)
    ]
    found: dict[tuple[str, int], list[EpisodeRecord]] = {}

    def keep(entry: ChainDay) -> None:
        ledger.append(line_of(entry))
        if progress is not None:
            progress(1 / per_day)

    def done(job: HouseholdJob, records: list[EpisodeRecord]) -> None:
        found[(job.condition.name, job.index)] = records

    try:
        _live_all(jobs, kept, workers, (backend, address), keep, done)
    except EvaluationStopped as err:
        ledger.save()
        kept_now = already + ledger.count
        raise EvaluationStopped(err.signum, kept_now, total, out / EPISODES, "chain day") from None
    finally:
        shutil.rmtree(workdir / "values", ignore_errors=True)
    metrics, kept_days = day_metrics(households, days, seed, conditions, found, brain_args, command, policies)
    _write(out, metrics, kept_days, workdir)
    return metrics


def _live_all(
    jobs: Sequence[HouseholdJob],
    kept: Mapping[tuple[str, int], Mapping[tuple[str, int], ChainDay]],
    workers: int,
    backend: tuple[str, str | None],
    keep: Keep,
    done: Callable[[HouseholdJob, list[EpisodeRecord]], None],
) -> None:
    """Every household of ``jobs``, on ``backend`` (its name, and a Ray cluster's address)."""
    if backend[0] == "ray":
        from .rayhouseholds import live_on_ray

        live_on_ray(jobs, kept, workers, backend[1], keep, done)
        return

    def live(job: HouseholdJob) -> list[EpisodeRecord]:
        return run_household(job, kept.get((job.condition.name, job.index), {}), keep)

    run_chunks([[job] for job in jobs], lambda chunk: [live(chunk[0])], workers, done)


def _write(
    out: Path, metrics: HouseholdEvaluation, episodes: Mapping[str, list[dict[str, Any]]], workdir: Path
) -> None:
    """``episodes.json`` (every day's record by condition), ``report.md`` and ``metrics.json``;
    then the evaluation is finished and its scratch folder pruned."""
    write_text(out / "episodes.json", json.dumps(episodes, indent=1) + "\n")
    write_text(out / "report.md", days_report(metrics, out))
    document = metrics.to_builtins()  # the one place the typed summary becomes JSON
    write_text(out / "metrics.json", json.dumps(document, indent=2) + "\n")  # last: it marks it done
    finished(out)
    prune_work(workdir)
