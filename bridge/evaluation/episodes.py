"""``toyroom eval``: the brain measured on random episodes whose true minds are known.

Each episode is a random scenario (``toyroom generate``) on the paper map or one
of two generated houses, with autonomous simulated people. It runs twice, each time an
engine and a brain process over loopback Zenoh in lock-step: the robot observing (the BToM
brain live, with ``truebelief`` and ``perceptonly`` as shadow observers of the same ticks,
:mod:`brain.outputs.shadows`), and the BToM brain with the robot acting.
The evaluator listens to ``brain/mind`` and ``engine/truth`` and scores every
tick (:mod:`bridge.evaluation.metrics`); robot success is whether each person ends the episode with
what they want (playing with their preferred item, or outside if they want to leave), with
and without the robot. Episodes run ``workers`` at a time, locally or as Ray tasks.
"""

from __future__ import annotations

import json
import logging
import statistics
import subprocess
import sys
import tempfile
from collections.abc import Callable
from concurrent.futures import ThreadPoolExecutor, as_completed
from pathlib import Path

from protocol import Observer

from .intervals import intervals
from .metrics import Counts, Outcome, majority_counts
from .report import report
from .runs import MOTION, RunResult, RunSpec, run_once

log = logging.getLogger("toyroom.eval")

BRAIN_OBSERVERS = Observer.names()
OBSERVERS = (*BRAIN_OBSERVERS, MOTION)
"""Every observer scored: the brain's three, and the motion heuristic."""
BTOM = Observer.BTOM.value
RUN_ATTEMPTS = 3
"""How often one run is tried when a node process fails (a crash, not a wrong estimate)."""
MAPS = ("paper", "house-a", "house-b")
MAJORITY = "majority"
"""A majority-class baseline scored on the same ticks: always the most common true preference
(of the episodes scored: it is fitted on them), never a false belief, no belief."""


def map_of(index: int) -> str:
    """The map episode ``index`` of a sweep is drawn on (they cycle through ``MAPS``)."""
    return MAPS[index % len(MAPS)]


def generate(directory: Path, index: int, seed: int) -> Path:
    """Write episode ``index`` of a sweep with ``seed`` (on the map :func:`map_of` says)."""
    map_name = map_of(index)
    result = subprocess.run(
        [
            sys.executable,
            "-m",
            "sim2d",
            "generate",
            "--map",
            map_name,
            "--seed",
            str(seed * 1000 + index),
            "--max-ticks",
            "1000",
            "--out",
            str(directory),
        ],
        capture_output=True,
        text=True,
        timeout=120,
        check=False,
    )
    if result.returncode != 0:
        raise RuntimeError(f"generating episode {index}: {result.stderr.strip()}")
    return Path(result.stdout.strip())


def episode_runs(scenario: Path, brain_args: tuple[str, ...] = ()) -> list[RunSpec]:
    """Two runs: the robot observing (BToM live, the baselines as shadows of the same ticks:
    an observing robot changes nothing, so one run serves every observer), then acting."""
    return [
        RunSpec(scenario, BRAIN_OBSERVERS[0], "observe", shadows=BRAIN_OBSERVERS[1:], brain_args=brain_args),
        RunSpec(scenario, BTOM, "act", brain_args=brain_args),
    ]


def run_episode(index: int, seed: int, workdir: str, brain_args: tuple[str, ...] = ()) -> dict[str, object]:
    """Everything about one episode, as plain data (so a Ray task can return it); an
    episode whose runs kept failing comes back with its ``error`` and no scores."""
    try:
        return _episode(index, seed, workdir, brain_args)
    except Exception as err:
        log.error("episode %d failed: %s", index, err)
        return {
            "index": index,
            "map": map_of(index),
            "scenario": f"episode-{index}",
            "error": f"{type(err).__name__}: {err}",
        }


def _episode(index: int, seed: int, workdir: str, brain_args: tuple[str, ...]) -> dict[str, object]:
    directory = Path(workdir)
    scenario = generate(directory / "scenarios", index, seed)
    logs = directory / "logs"
    logs.mkdir(parents=True, exist_ok=True)
    out: dict[str, object] = {"index": index, "map": map_of(index), "scenario": scenario.stem}
    failures: list[str] = []
    for spec in episode_runs(scenario, brain_args):
        for observer, result in _run_with_retries(spec, logs, failures).items():
            key = observer if spec.robot == "observe" else "robot"
            out[key] = {
                "counts": result.counts.__dict__,
                "outcome": result.outcome.per_person,
                "ticks_to_goal": result.outcome.ticks_to_goal,
                "episode_ticks": result.outcome.ticks,
                "ticks": result.ticks,
            }
    out["failed_runs"] = failures
    return out


def _run_with_retries(spec: RunSpec, logs: Path, failures: list[str]) -> dict[str, RunResult]:
    """``run_once``, again (up to ``RUN_ATTEMPTS`` times) when a node process failed; each
    failure is kept (with its log, renamed) and counted in ``metrics.json``. A run is
    deterministic, so a retry measures the same episode."""
    for attempt in range(1, RUN_ATTEMPTS + 1):
        try:
            return run_once(spec, logs)
        except (RuntimeError, OSError, subprocess.SubprocessError) as err:
            failures.append(str(err))
            log.warning("%s (attempt %d of %d)", err, attempt, RUN_ATTEMPTS)
            tag = f"{spec.scenario.stem}-{spec.observer}-{spec.robot}"
            for path in logs.glob(f"{tag}.*.log"):
                path.rename(path.with_suffix(f".failed{attempt}.log"))
            if attempt == RUN_ATTEMPTS:
                raise
    raise AssertionError("unreachable")


def _count(value: object) -> int:
    return len(value) if isinstance(value, list) else 0


def aggregate(episodes: list[dict[str, object]], seed: int) -> dict[str, object]:
    """``metrics.json``'s content from every episode's results (failed episodes are
    counted in ``episodes_failed`` and left out of the scores)."""
    failed = [e for e in episodes if "error" in e]
    episodes = [e for e in episodes if "error" not in e]
    totals = {observer: Counts() for observer in OBSERVERS}
    per_episode: dict[str, list[Counts]] = {observer: [] for observer in (*OBSERVERS, MAJORITY)}
    with_robot = Outcome()
    without = Outcome()
    waits: dict[str, list[int]] = {"robot": [], BTOM: []}
    for episode in episodes:
        for observer in OBSERVERS:
            counts = Counts(**episode[observer]["counts"])  # type: ignore[index]
            totals[observer].add(counts)
            per_episode[observer].append(counts)

        for outcome, key in ((with_robot, "robot"), (without, BTOM)):
            run = episode[key]
            assert isinstance(run, dict)
            for ok in run["outcome"].values():
                outcome.people += 1
                outcome.successes += bool(ok)
            for tick in run.get("ticks_to_goal", {}).values():  # never reached: the episode's length
                waits[key].append(tick if tick is not None else run["episode_ticks"])
    goal = max(totals[BTOM].pref_truth, key=lambda g: (totals[BTOM].pref_truth[g], g), default="")
    per_episode[MAJORITY] = [majority_counts(c, goal) for c in per_episode[BTOM]]
    bounds, differences = intervals(per_episode, seed)
    return {
        "episodes": len(episodes),
        "seed": seed,
        "episodes_failed": len(failed),
        "failed_runs_retried": sum(_count(e.get("failed_runs")) for e in episodes),
        "observers": {observer: totals[observer].metrics() for observer in OBSERVERS}
        | {MAJORITY: totals[BTOM].majority().metrics()},
        "intervals": bounds,
        "paired_differences": differences,
        "robot": {"with": with_robot.rate, "without": without.rate},
        "ticks_to_goal": {
            "with": statistics.fmean(waits["robot"]) if waits["robot"] else None,
            "without": statistics.fmean(waits[BTOM]) if waits[BTOM] else None,
        },
    }


def evaluate(
    episodes: int,
    seed: int,
    out: Path,
    *,
    workers: int = 2,
    backend: str = "local",
    progress: Callable[[int], None] | None = None,
    brain_args: tuple[str, ...] = (),
) -> dict[str, object]:
    """Run every episode and write ``metrics.json`` and ``report.md`` into ``out``
    (``brain_args``: more options for every brain, e.g. ``--set belief_model=graded``)."""
    out.mkdir(parents=True, exist_ok=True)
    workdir = tempfile.mkdtemp(prefix="toyroom-eval-", dir=out)
    results: list[dict[str, object]]
    if backend == "ray":
        from .raybackend import run_with_ray

        results = run_with_ray(run_episode, episodes, seed, workdir, workers, progress, brain_args)
    else:
        with ThreadPoolExecutor(max_workers=workers) as pool:
            futures = [pool.submit(run_episode, i, seed, workdir, brain_args) for i in range(episodes)]
            results = []
            with (out / "episodes.jsonl").open("w") as partial:  # kept as they finish
                for future in as_completed(futures):
                    results.append(future.result())
                    partial.write(json.dumps(results[-1]) + "\n")
                    partial.flush()
                    if progress is not None:
                        progress(1)
    results.sort(key=lambda r: int(r["index"]))  # type: ignore[call-overload]
    metrics = aggregate(results, seed)
    metrics["brain_args"] = list(brain_args)
    by_map = {name: aggregate([r for r in results if r["map"] == name], seed) for name in MAPS}
    (out / "metrics.json").write_text(json.dumps(metrics, indent=2) + "\n")
    (out / "episodes.json").write_text(json.dumps(results, indent=1) + "\n")
    (out / "report.md").write_text(report(metrics, by_map, out))
    return metrics
