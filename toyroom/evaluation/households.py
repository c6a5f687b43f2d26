"""``toyroom eval --days N``: households lived over days, the brain with a memory of each person.

Episode ``i`` of a sweep becomes a household of ``N`` days (:mod:`sim2d.generation.households`):
day 1 is the episode itself, and each later day starts where the day before ended in *that
run*, so every run is a chain of days of its own (:class:`Chain`):

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

import dataclasses
import json
import logging
import shutil
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import msgspec

from bridge.recording.atomic import write_text
from protocol import OBSERVING, Morning, Observer

from .conditions import Condition
from .days import HELP_METRIC, LATER, by_day, plot, table
from .episodes import BRAIN_OBSERVERS, OBSERVERS, _recorded, _run_with_retries
from .generation import generate_day, map_of
from .interrupt import NODES
from .pool import run_chunks
from .records import EpisodeRecord, RunScores
from .runs import RunSpec

log = logging.getLogger("toyroom.eval")

BTOM = Observer.BTOM.value
FRESH = "fresh"
"""The suffix of a chain whose brain has no memory: a first day every day."""


@dataclass(frozen=True)
class Chain:
    """One run of every day of a household."""

    name: str
    robot: str
    """``observe`` or ``act``."""
    policy: str = "tom"
    memory: bool = True
    follows: str | None = None
    """Run on the days of this other chain (an observer, which changes nothing) instead of its own."""

    def key(self, observer: str) -> str:
        """The key a run's scores for ``observer`` go under in a day's record."""
        if self.robot == "act":
            return f"robot-{self.policy}" + ("" if self.memory else f"-{FRESH}")
        return observer if self.memory else f"{observer}-{FRESH}"


def chains(policies: Sequence[str]) -> list[Chain]:
    """The chains of a household (the module's docstring), observers first."""
    return [
        Chain("observe", "observe"),
        Chain(f"observe-{FRESH}", "observe", memory=False, follows="observe"),
        *(Chain(policy, "act", policy) for policy in policies),
        *([Chain(f"tom-{FRESH}", "act", "tom", memory=False)] if "tom" in policies else []),
    ]


@dataclass(frozen=True)
class HouseholdJob:
    """Household ``index`` of a sweep with ``seed`` under ``condition``, lived ``days`` days."""

    index: int
    seed: int
    workdir: str
    days: int
    condition: Condition = Condition()
    brain_args: tuple[str, ...] = ()
    policies: tuple[str, ...] = ("tom",)
    max_ticks: int = 1000
    record: bool = False


def run_household(job: HouseholdJob) -> list[EpisodeRecord]:
    """Every day of the household, one record each (a day whose runs kept failing comes back
    with its ``error``, as do the days after it in the chains that failed)."""
    started = time.monotonic()
    home = Path(job.workdir) / job.condition.name / f"household-{job.index}"
    runs: dict[int, dict[str, RunScores]] = {d: {} for d in range(1, job.days + 1)}
    seconds: dict[int, dict[str, float]] = {d: {} for d in range(1, job.days + 1)}
    scenarios: dict[str, dict[int, Path]] = {}
    failures: dict[int, list[str]] = {d: [] for d in range(1, job.days + 1)}
    errors: dict[int, str] = {}
    for chain in chains(job.policies):
        try:
            scenarios[chain.name] = _live(job, chain, home, scenarios, runs, seconds, failures)
        except Exception as err:  # a chain that fails stops there; the others go on
            day = 1 + len([d for d in runs if chain.key(BTOM) in runs[d]])
            errors.setdefault(day, f"{chain.name}, day {day}: {type(err).__name__}: {err}")
            log.error("household %d: %s", job.index, errors[day])
    took = (time.monotonic() - started) / job.days
    first_error = min(errors, default=job.days + 1)
    return [
        EpisodeRecord(
            index=job.index,
            map=map_of(job.index),
            scenario=scenarios.get("observe", {}).get(day, Path(f"household-{job.index}-d{day}")).stem,
            run_seconds=seconds[day] if day < first_error else None,
            runs=runs[day] if day < first_error else {},
            error=errors.get(day)
            or (f"an earlier day failed (day {first_error})" if day > first_error else None),
            failed_runs=failures[day] or None,
            seconds=took if day < first_error else None,
            day=day,
        )
        for day in range(1, job.days + 1)
    ]


def _live(
    job: HouseholdJob,
    chain: Chain,
    home: Path,
    scenarios: dict[str, dict[int, Path]],
    runs: dict[int, dict[str, RunScores]],
    seconds: dict[int, dict[str, float]],
    failures: dict[int, list[str]],
) -> dict[int, Path]:
    """Run ``chain`` through every day; its scenarios by day."""
    days: dict[int, Path] = {}
    morning: Path | None = None
    memory = home / "memory" / f"{chain.name}.sqlite"
    memory.parent.mkdir(parents=True, exist_ok=True)
    for day in range(1, job.days + 1):
        if chain.follows is not None:
            scenario = scenarios[chain.follows][day]
        else:
            scenario = generate_day(
                home / "scenarios" / chain.name,
                job.index,
                job.seed,
                job.condition,
                job.max_ticks,
                day,
                morning,
            )
        days[day] = scenario
        spec = _spec(job, chain, scenario, memory)
        began = time.monotonic()
        logs = home / "logs" / chain.name
        logs.mkdir(parents=True, exist_ok=True)
        result = _run_with_retries(spec, logs, failures[day])
        seconds[day][f"{chain.name}"] = time.monotonic() - began
        for observer, scored in result.items():
            runs[day][chain.key(observer)] = RunScores.of(scored)
        live = result[spec.observer].morning
        if live is None and day < job.days:
            raise RuntimeError(f"day {day} left no truth to start day {day + 1} from")
        if live is not None:
            morning = home / "mornings" / chain.name / f"day{day}.json"
            morning.parent.mkdir(parents=True, exist_ok=True)
            morning.write_bytes(msgspec.json.encode(live))
    return days


def _spec(job: HouseholdJob, chain: Chain, scenario: Path, memory: Path) -> RunSpec:
    """The run of ``chain`` on ``scenario``: an observer with the baselines as shadows (the
    chain with memory), or the robot acting by the chain's policy."""
    values = ("--values-cache", str(Path(job.workdir) / "values"))
    remember = ("--memory", str(memory)) if chain.memory else ()
    args = (*job.condition.brain_args(), *job.brain_args, *values, *remember)
    shadows = tuple(BRAIN_OBSERVERS[1:]) if chain.robot == "observe" and chain.memory else ()
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
    policies: Sequence[str] = ("tom",),
    record: bool = False,
    max_ticks: int = 1000,
    progress: Callable[[int], None] | None = None,
) -> dict[str, Any]:
    """Live ``households`` households of every condition for ``days`` days each and write
    ``metrics.json`` (per condition: ``by_day`` and ``later``, :mod:`.days`), ``episodes.json``
    (every day's record), ``report.md`` (the table by day) and ``days-<condition>.png``
    (help by day) into ``out``. Not resumable: a stopped evaluation starts again.

    Raises:
        EvaluationStopped: a stop signal came (:mod:`.interrupt`).
    """
    out.mkdir(parents=True, exist_ok=True)
    NODES.reset()
    workdir = out / "work"
    jobs = [
        HouseholdJob(i, seed, str(workdir), days, c, brain_args, tuple(policies), max_ticks, record)
        for c in conditions
        for i in range(households)
    ]
    found: dict[tuple[str, int], list[EpisodeRecord]] = {}

    def done(job: HouseholdJob, records: list[EpisodeRecord]) -> None:
        found[(job.condition.name, job.index)] = records
        if progress is not None:
            progress(1)

    try:
        run_chunks([[job] for job in jobs], lambda chunk: [run_household(chunk[0])], workers, done)
    finally:
        shutil.rmtree(workdir / "values", ignore_errors=True)
    observers = (*OBSERVERS, f"{BTOM}-{FRESH}")
    summaries, kept = [], {}
    for condition in conditions:
        records = [r for i in range(households) for r in found[(condition.name, i)]]
        kept[condition.name] = [r.to_builtins() for r in records]
        summary = {**dataclasses.asdict(condition), "name": condition.name}
        summary |= by_day(records, days, seed, observers)
        summaries.append(summary)
    metrics = {
        "households": households,
        "days": days,
        "seed": seed,
        "brain_args": list(brain_args),
        "policies": [*policies, OBSERVING],
        "command": command,
        "observers": list(observers),
        "conditions": summaries,
    }
    write_text(out / "episodes.json", json.dumps(kept, indent=1) + "\n")
    write_text(out / "report.md", days_report(metrics, out))
    write_text(out / "metrics.json", json.dumps(metrics, indent=2) + "\n")  # last: it marks it done
    return metrics


def days_report(metrics: Mapping[str, Any], out: Path) -> str:
    """``report.md`` of a households evaluation, each condition's plot drawn into ``out``."""
    lines = [
        f"# Households: {metrics['households']} per condition, {metrics['days']} days each, "
        f"seed {metrics['seed']}",
        "",
    ]
    if metrics.get("command"):
        lines += ["```", metrics["command"], "```", ""]
    lines += [
        f"Per day: `{HELP_METRIC}` (ticks from the day's start to the goal of the people with a false "
        "belief about what they wanted in any run of the day; lower is better) per robot policy "
        "(`none`: the robot observing; `-fresh`: a brain with no memory, a first day every day), "
        "the first policy minus each other (paired on the same people), and the share of revealed "
        "false beliefs each observer flagged before the person reached the place (%). In brackets: "
        f"bootstrap 95% intervals. `{LATER}+`: days {LATER} on, households resampled as wholes.",
        "",
    ]
    for condition in metrics["conditions"]:
        picture = plot(condition, out / f"days-{condition['name']}.png")
        lines += [f"## {condition['name']}", "", *table(condition, metrics["observers"]), ""]
        lines += [f"![help by day]({picture.name})", ""]
    return "\n".join(lines)
