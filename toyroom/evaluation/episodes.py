"""``toyroom eval``: the brain measured on random episodes whose true minds are known.

Each episode is a random scenario (``toyroom generate``) on the paper map or one
of two generated houses, with autonomous simulated people. It runs twice, each time an
engine and a brain process over loopback Zenoh in lock-step: the robot observing (the BToM
brain live, with ``truebelief`` and ``perceptonly`` as shadow observers of the same ticks,
:mod:`brain.outputs.shadows`), and the BToM brain with the robot acting.
The evaluator listens to ``engine/truth``, reads the brain's minds from its run log
(:mod:`toyroom.evaluation.runs`) and scores every tick (:mod:`toyroom.evaluation.metrics`);
robot success is whether each person ends the episode with what they want (playing with
their preferred item, or outside if they want to leave), with and without the robot.
Episodes run ``workers`` at a time, locally or as Ray tasks.
"""

from __future__ import annotations

import dataclasses
import json
import logging
import shutil
import subprocess
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path

from bridge.recording.atomic import OutputError, write_text
from protocol import MAX_TICKS, OBSERVING, EpisodeKind, Minds, Observer, Perception, Policy, RobotMode

from .aggregate import aggregate, by_task
from .batches import run_batch
from .conditions import Condition
from .folder import prune_scratch
from .generation import MAPS, generate, map_of, scenarios_of
from .interrupt import NODES, EvaluationStopped
from .noroom import check_room, stopped_for_room
from .planned import policy_table
from .pool import run_chunks
from .records import EpisodeRecord, RunKey, RunScores
from .report import report
from .resume import EPISODES, Ledger, begin, finished, plan_of
from .runs import MOTION, RunResult, RunSpec, run_once
from .summary import ConditionSummary, Evaluation
from .timing import cpu_seconds, timing

log = logging.getLogger("toyroom.eval")

BRAIN_OBSERVERS = Observer.names()
OBSERVERS = (*BRAIN_OBSERVERS, MOTION)
"""Every observer scored: the brain's three, and the motion heuristic."""
BTOM = Observer.BTOM.value
RUN_ATTEMPTS = 3
"""How often one run is tried when a node process fails (a crash, not a wrong estimate)."""
BATCH = 10
"""Episodes of one condition whose runs share their node processes (:func:`batches`)."""


@dataclass(frozen=True)
class EpisodeJob:
    """Episode ``index`` of a sweep with ``seed`` under ``condition`` (plain data, so a Ray
    task can take it), its files under ``workdir``."""

    index: int
    seed: int
    workdir: str
    condition: Condition = Condition()
    brain_args: tuple[str, ...] = ()
    policies: tuple[Policy, ...] = (Policy.TOM,)
    """The acting robot's policies, one run each (``RobotSettings.policy``)."""
    record: bool = False
    """Keep every run's MCAP recording in ``recordings/<condition>/`` of the output folder."""
    max_ticks: int = MAX_TICKS
    """The episode's length."""
    scenario: str = ""
    """The episode's scenario file when it was generated beforehand (:func:`generate_all`);
    empty: the job generates it."""


def episode_runs(
    scenario: Path,
    brain_args: tuple[str, ...] = (),
    perception: Perception = Perception.OMNISCIENT,
    policies: Sequence[Policy] = (Policy.TOM,),
) -> list[RunSpec]:
    """The robot observing (BToM live, the baselines as shadows of the same ticks: an
    observing robot changes nothing, so one run serves every observer), then one run with
    the robot acting per policy."""
    observe = RunSpec(
        scenario,
        BRAIN_OBSERVERS[0],
        RobotMode.OBSERVE,
        shadows=BRAIN_OBSERVERS[1:],
        brain_args=brain_args,
        perception=perception,
    )
    acting = [
        RunSpec(scenario, BTOM, RobotMode.ACT, brain_args=brain_args, policy=policy, perception=perception)
        for policy in policies
    ]
    return [observe, *acting]


def run_episode(job: EpisodeJob) -> EpisodeRecord:
    """Everything about one episode (:class:`~.records.EpisodeRecord`); an episode whose
    runs kept failing comes back with its ``error`` and no scores (a full disk: :mod:`.noroom`)."""
    try:
        return _episode(job)
    except (EvaluationStopped, OutputError):
        raise
    except Exception as err:
        check_room(err, Path(job.workdir), f"episode {job.index}")  # generating it found no room
        log.error("episode %d failed: %s", job.index, err)
        return EpisodeRecord(
            index=job.index,
            map=map_of(job.index),
            scenario=f"episode-{job.index}",
            error=f"{type(err).__name__}: {err}",
        )


def _episode(job: EpisodeJob) -> EpisodeRecord:
    started = time.monotonic()
    scenario, specs = episode_specs(job)
    logs = Path(job.workdir) / job.condition.name / "logs"
    failures: list[str] = []
    results, seconds = [], []
    for spec in specs:
        run_started = time.monotonic()
        results.append(_run_with_retries(spec, logs, failures))
        seconds.append(time.monotonic() - run_started)
    return episode_entry(job, scenario, specs, results, seconds, failures, time.monotonic() - started)


def episode_specs(job: EpisodeJob) -> tuple[Path, list[RunSpec]]:
    """The job's scenario (generated here unless it was beforehand) and its runs
    (:func:`episode_runs`, with the condition's and the job's options)."""
    directory = Path(job.workdir) / job.condition.name
    condition = job.condition
    if job.scenario:
        scenario = Path(job.scenario)
    else:
        scenario = generate(directory / "scenarios", job.index, job.seed, condition.spec(job.max_ticks))
    (directory / "logs").mkdir(parents=True, exist_ok=True)
    values = ("--values-cache", str(Path(job.workdir) / "values"))  # each map solved once per evaluation
    args = (*job.condition.brain_args(), *job.brain_args, *values)
    engine_args: tuple[str, ...] = ()
    if job.condition.minds == Minds.MODEL:  # people act by the planner under the run's settings
        engine_args = ("--policy", str(policy_table(scenario, job.brain_args, directory / "policies")))
    specs = []
    for spec in episode_runs(scenario, args, job.condition.perception, job.policies):
        spec = dataclasses.replace(spec, engine_args=engine_args)
        if job.record:
            spec = _recorded(spec, Path(job.workdir).parent / "recordings" / job.condition.name)
        specs.append(spec)
    return scenario, specs


def episode_entry(
    job: EpisodeJob,
    scenario: Path,
    specs: Sequence[RunSpec],
    results: Sequence[dict[str, RunResult]],
    seconds: Sequence[float],
    failures: list[str],
    took: float,
) -> EpisodeRecord:
    """Everything about one episode: each run's scores (``results``, in the order of
    ``specs``), its seconds, the failed attempts, and the episode's seconds."""
    run_seconds: dict[str, float] = {}
    runs: dict[str, RunScores] = {}
    for spec, result, spent in zip(specs, results, seconds, strict=True):
        run_seconds[spec.tag.removeprefix(f"{scenario.stem}-")] = spent
        for observer, scored in result.items():
            key = RunKey(observer) if spec.robot == RobotMode.OBSERVE else RunKey.acting(spec.policy)
            runs[str(key)] = RunScores.of(scored)
    return EpisodeRecord(
        index=job.index,
        map=map_of(job.index),
        scenario=scenario.stem,
        run_seconds=run_seconds,
        runs=runs,
        failed_runs=failures,
        seconds=took,
    )


def _recorded(spec: RunSpec, directory: Path) -> RunSpec:
    """``spec`` with its brain recording the run to ``directory/<tag>.mcap``."""
    directory.mkdir(parents=True, exist_ok=True)
    return dataclasses.replace(
        spec, brain_args=(*spec.brain_args, "--record", str(directory / f"{spec.tag}.mcap"))
    )


def _run_with_retries(spec: RunSpec, logs: Path, failures: list[str]) -> dict[str, RunResult]:
    """``run_once``, again (up to ``RUN_ATTEMPTS`` times) when a node process failed; each
    failure is kept (with its log, renamed) and counted in ``metrics.json``. A run is
    deterministic, so a retry measures the same episode; one that failed for a full disk is
    not tried again (:func:`.noroom.check_room` raises ``OutputError``)."""
    for attempt in range(1, RUN_ATTEMPTS + 1):
        try:
            return run_once(spec, logs)
        except (RuntimeError, OSError, subprocess.SubprocessError) as err:
            NODES.check()  # its nodes were stopped by a signal: no failure of the run
            check_room(err, logs, spec.tag)
            failures.append(str(err))
            log.warning("%s (attempt %d of %d)", err, attempt, RUN_ATTEMPTS)
            tag = spec.tag
            for path in logs.glob(f"{tag}.*.log"):
                path.rename(path.with_suffix(f".failed{attempt}.log"))
            if attempt == RUN_ATTEMPTS:
                raise
    raise AssertionError("unreachable")


def evaluate(
    episodes: int,
    seed: int,
    out: Path,
    *,
    conditions: Sequence[Condition] = (Condition(),),
    workers: int = 2,
    backend: str = "local",
    progress: Callable[[int], None] | None = None,
    brain_args: tuple[str, ...] = (),
    command: str = "",
    policies: Sequence[Policy] = (Policy.TOM,),
    record: bool = False,
    max_ticks: int = MAX_TICKS,
    batch: int = BATCH,
    address: str | None = None,
    fresh: bool = False,
    notify: Callable[[str], None] | None = None,
) -> Evaluation:
    """Run every episode of every condition and write ``metrics.json``, ``episodes.json``
    and ``report.md`` into ``out`` (``brain_args``: more options for every brain, e.g.
    ``--set belief_model=point``; ``command``: the command line, for the report;
    ``record``: keep every run's MCAP recording under ``out/recordings/``; ``max_ticks``: each
    episode's length; ``batch``: at most this many episodes share their node processes, 1:
    none do, :func:`batches`; ``address``: with the Ray backend, the cluster's, default
    ``RAY_ADDRESS``, :mod:`.rayepisodes`). An unfinished evaluation of the same plan in
    ``out`` is resumed, its finished episodes kept (:mod:`.resume`; ``notify`` is told how
    many), unless ``fresh``.

    Raises:
        IncompatibleRun: ``out`` holds an unfinished evaluation of another plan.
        EvaluationStopped, OutputError: a stop signal came (:mod:`.interrupt`), or the disk
            is full (:mod:`.noroom`); the finished episodes are kept.
    """
    out.mkdir(parents=True, exist_ok=True)
    NODES.reset()
    plan = plan_of(episodes, seed, conditions, brain_args, policies, record, max_ticks)
    state, entries = begin(out, plan, [c.name for c in conditions], fresh)
    total = episodes * len(conditions)
    if entries and notify is not None:
        notify(f"resuming the unfinished evaluation in {out}: {len(entries)} of {total} episodes kept")
    if entries and progress is not None:
        progress(len(entries))
    workdir = str(out / state.workdir)
    ledger = Ledger(out, state, cpu_seconds)  # generating the episodes counts too

    def done(job: EpisodeJob, entry: EpisodeRecord) -> None:
        ledger.keep(job.condition.name, entry)
        entries[(job.condition.name, job.index)] = entry
        if progress is not None:
            progress(1)

    try:
        jobs = [
            EpisodeJob(i, seed, workdir, c, brain_args, tuple(policies), record, max_ticks, scenario)
            for c in conditions
            for i, scenario in enumerate(scenarios_of(Path(workdir), episodes, seed, c, max_ticks))
            if (c.name, i) not in entries
        ]
        _run_jobs(jobs, workers, backend, done, batch, address)
        chunks = [[entries[(c.name, i)] for i in range(episodes)] for c in conditions]
        used = None if backend == "ray" else ledger.cpu()
        metrics = Evaluation(
            episodes=episodes,
            seed=seed,
            brain_args=list(brain_args),
            policies=[*policies, OBSERVING],
            command=command,
            timing=timing([r for chunk in chunks for r in chunk], ledger.seconds(), workers, used),
            conditions=[_summary(c, chunk, seed) for c, chunk in zip(conditions, chunks, strict=True)],
        )
        _write(out, metrics, {c.name: chunk for c, chunk in zip(conditions, chunks, strict=True)}, workdir)
    except EvaluationStopped as err:
        ledger.save()
        raise EvaluationStopped(err.signum, len(entries), total, out / EPISODES) from None
    except OutputError as err:  # a full disk: the finished episodes are kept, to resume
        raise stopped_for_room(err, len(entries), total, out / EPISODES) from None
    finally:  # the solved Q-values (--values-cache) are a cache of this evaluation only
        shutil.rmtree(Path(workdir) / "values", ignore_errors=True)
    return metrics


def _write(out: Path, metrics: Evaluation, episodes: dict[str, list[EpisodeRecord]], workdir: str) -> None:
    """``metrics.json``, ``episodes.json`` (each condition's episodes) and ``report.md``;
    then the evaluation is no longer an unfinished one (:mod:`.resume`), and its scratch
    folder ``workdir`` keeps only its logs and scenarios (:mod:`.folder`)."""
    kept = {name: [entry.to_builtins() for entry in chunk] for name, chunk in episodes.items()}
    write_text(out / "episodes.json", json.dumps(kept, indent=1) + "\n")
    write_text(out / "report.md", report(metrics, out))
    write_text(
        out / "metrics.json", json.dumps(metrics.to_builtins(), indent=2) + "\n"
    )  # last: it marks it done
    finished(out)
    prune_scratch(Path(workdir))


def _summary(condition: Condition, chunk: list[EpisodeRecord], seed: int) -> ConditionSummary:
    """One condition's numbers, from its episodes (in order of index)."""
    return ConditionSummary(
        condition=condition,
        numbers=aggregate(chunk, seed, OBSERVERS),
        by_map={m: aggregate([r for r in chunk if r.map == m], seed, OBSERVERS) for m in MAPS},
        by_task=by_task(condition, chunk, seed, OBSERVERS) if condition.kind == EpisodeKind.TASKS else None,
    )


def batches(jobs: Sequence[EpisodeJob], workers: int, size: int) -> list[list[EpisodeJob]]:
    """``jobs`` (in order, by condition) in batches of at most ``size`` episodes of one
    condition, smaller where that leaves a worker idle; an episode that cannot share its
    processes (its runs are recorded, or its engine has options of its own) alone."""
    out: list[list[EpisodeJob]] = []
    for condition in dict.fromkeys(job.condition for job in jobs):
        chunk = [job for job in jobs if job.condition == condition]
        if not all(_shares(job) for job in chunk):
            out += [[job] for job in chunk]
            continue
        step = max(1, min(size, -(-len(chunk) // max(1, workers))))
        out += [chunk[i : i + step] for i in range(0, len(chunk), step)]
    return out


def _shares(job: EpisodeJob) -> bool:
    """Whether a job's runs can share processes with other episodes' (a recording per run,
    or a planner table per episode for the engine, need a process each)."""
    return not job.record and job.condition.minds != Minds.MODEL


def run_episodes(jobs: Sequence[EpisodeJob]) -> list[EpisodeRecord]:
    """:func:`run_episode` of each job, in order, the runs of all of them sharing an engine
    process and a brain process per kind of run (:mod:`toyroom.evaluation.batches`); an
    episode whose batch did not finish it is run again alone (its entry's ``failed_runs``
    says so), as is every job when sharing fails as a whole."""
    if len(jobs) == 1 or not all(_shares(job) for job in jobs):
        return [run_episode(job) for job in jobs]
    started = time.monotonic()
    try:
        prepared = [episode_specs(job) for job in jobs]
        logs = Path(jobs[0].workdir) / jobs[0].condition.name / "logs"
        batch = run_batch([specs for _, specs in prepared], logs)
    except (RuntimeError, OSError, subprocess.SubprocessError) as err:
        log.warning("a batch of %d episodes failed (%s): each is run alone", len(jobs), err)
        return [run_episode(job) for job in jobs]
    took = (time.monotonic() - started) / len(jobs)
    out = []
    for job, (scenario, specs), scores in zip(jobs, prepared, batch.scores, strict=True):
        if scores is None:
            entry = run_episode(job)
            again = f"episode {job.index}: its batch did not finish it"
            entry.failed_runs = [again, *(entry.failed_runs or [])]
        else:
            entry = episode_entry(job, scenario, specs, scores, batch.seconds, [], took)
        out.append(entry)
    return out


def _run_jobs(
    jobs: list[EpisodeJob],
    workers: int,
    backend: str,
    done: Callable[[EpisodeJob, EpisodeRecord], None],
    batch: int = BATCH,
    address: str | None = None,
) -> None:
    """Every job, ``done(job, entry)`` as each comes back (``batch``: episodes per batch,
    locally, :func:`batches`; with Ray, each episode a task on the cluster at ``address``,
    :mod:`.rayepisodes`).

    Raises:
        EvaluationStopped: a stop signal came; what came back before it went to ``done``.
    """
    if backend == "ray":
        from .rayepisodes import run_on_ray

        run_on_ray(jobs, workers, done, address)
        return
    run_chunks(batches(jobs, workers, batch), run_episodes, workers, done)
