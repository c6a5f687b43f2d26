"""``toyroom eval`` end to end: the local backend (no Ray needed) writes every metric and
reports progress per episode; the Ray backend (a local Ray instance, loopback only) gives the
same metrics for the same seed."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from protocol import EpisodeKind, EpisodeSpec, Minds
from toyroom.evaluation.conditions import Condition
from toyroom.evaluation.episodes import evaluate
from toyroom.evaluation.generation import check_autonomy, generate, generate_all, map_of
from toyroom.evaluation.scores import metric_names
from toyroom.evaluation.summary import Evaluation, Interval

EPISODES, SEED = 2, 5


@pytest.fixture(scope="module")
def local(tmp_path_factory: pytest.TempPathFactory) -> tuple[Evaluation, list[int], Path]:
    """The local backend's metrics, every progress call, and its output folder."""
    out = tmp_path_factory.mktemp("eval-local")
    calls: list[int] = []
    metrics = evaluate(EPISODES, SEED, out, workers=2, backend="local", progress=calls.append, record=True)
    return metrics, calls, out


def test_eval_record_keeps_every_run(local: tuple[Evaluation, list[int], Path], tmp_path: Path) -> None:
    """``--record``: each run's MCAP in ``recordings/<condition>/``, readable as a trace."""
    from bridge.recording.mcap import mcap_to_trace
    from bridge.recording.trace import read_trace

    _, _, out = local
    folder = out / "recordings" / "omniscient-simple-everyday"
    names = sorted(p.name for p in folder.glob("*.mcap"))
    want = sorted(
        f"gen-{m}-s{5000 + i}-btom-{a}.mcap"
        for i, m in enumerate(("paper", "house-a"))
        for a in ("observe", "act-tom")
    )
    assert names == want, f"expected {want}, got {names}"
    mcap_to_trace(folder / want[-1], tmp_path / "trace.jsonl")
    assert len(read_trace(tmp_path / "trace.jsonl").ticks) > 100


def test_local_eval_writes_every_metric(local: tuple[Evaluation, list[int], Path]) -> None:
    metrics, _, out = local
    assert metrics.episodes == EPISODES and metrics.seed == SEED
    assert json.loads((out / "metrics.json").read_text()) == json.loads(json.dumps(metrics.to_builtins()))
    (condition,) = json.loads((out / "metrics.json").read_text())["conditions"]
    assert (condition["perception"], condition["minds"], condition["kind"]) == (
        "omniscient",
        "simple",
        "everyday",
    )
    assert condition["episodes_failed"] == 0, f"episodes failed: {out / 'episodes.json'}"
    for observer in ("btom", "truebelief", "perceptonly", "motion", "majority"):
        values = condition["observers"][observer]
        assert list(values) == list(metric_names()), (
            f"{observer}: expected the record's metrics, got {list(values)}"
        )
        assert set(values["false_belief_f1"]) == set(values["goal_false_belief_f1"]) == {"mean", "lo", "hi"}
        assert set(values["brier"]) == set(values["brier_skill"]) == {"mean", "lo", "hi"}
        assert values["brier"]["mean"] is not None and 0.0 <= values["brier"]["mean"] <= 1.0
    assert condition["observers"]["btom"]["belief_tv"]["mean"] is not None
    assert set(condition["robot"]) == {"tom", "none"}
    for policy in condition["robot"].values():
        assert set(policy) == {
            "success",
            "ticks_to_goal_fb",
            "ticks_to_goal_any_fb",
            "ticks_from_false_belief",
            "wasted_trips",
            "interruptions",
            "cut",
            "cut_any_fb",
            "share_of_oracle",
            "share_of_oracle_any_fb",
        }, policy
        assert policy["wasted_trips"]["mean"] is not None
    tasks = condition["robot_tasks"]["tom"]
    assert set(tasks) == {"begun", "done", "dropped", "running", "unfinished_share"}, tasks
    assert tasks["begun"] == tasks["done"] + tasks["dropped"] + tasks["running"], tasks
    assert "none" not in condition["robot_tasks"], "the observing robot begins no task"
    report = (out / "report.md").read_text()
    assert "| policy | begun | done | dropped | running at the end | unfinished |" in report
    assert report.startswith(f"# Evaluation: {EPISODES} episodes per condition")
    assert "perceptonly` is an oracle" in report, "the omniscient / simple condition says why"
    assert (out / "metrics-omniscient-simple-everyday.png").stat().st_size > 0
    episodes = json.loads((out / "episodes.json").read_text())["omniscient-simple-everyday"]
    assert [e["map"] for e in episodes] == ["paper", "house-a"], episodes
    assert [e["scenario"] for e in episodes] == ["gen-paper-s5000", "gen-house-a-s5001"]
    assert set(episodes[0]["robot-tom"]["help"]) == {"A1", "A2"}
    timing = metrics.timing
    assert timing["workers"] == 2 and timing["seconds"] > 0
    assert timing["seconds_per_episode"] == pytest.approx(timing["seconds"] / EPISODES)
    assert set(timing["run_seconds_mean"]) == {"btom-observe", "btom-act-tom"}, timing
    assert f"{timing['seconds_per_episode']:.2f} s per episode" in report, "report.md gives the speed"
    cpu = timing["cpu_seconds_per_episode"]
    assert cpu["nodes"] > cpu["evaluator"] > 0, f"the nodes infer and step, the evaluator scores: {cpu}"
    assert f"CPU per episode: {sum(cpu.values()):.1f} s" in report, "report.md gives the CPU per episode"


def test_local_eval_progress_advances_per_episode(local: tuple[Evaluation, list[int], Path]) -> None:
    _, calls, _ = local
    assert calls == [1] * EPISODES, f"expected one progress(1) per episode, got {calls}"


@pytest.mark.sweep  # Ray starts its own cluster: a minute or more, beyond make test's budget
@pytest.mark.timeout(600)  # minutes on a loaded two-core machine
def test_ray_backend_agrees_with_local(local: tuple[Evaluation, list[int], Path], tmp_path: Path) -> None:
    pytest.importorskip("ray")
    result = subprocess.run(
        [
            *(sys.executable, "-m", "toyroom", "eval", "--episodes", str(EPISODES), "--seed", str(SEED)),
            *("--workers", "2", "--backend", "ray", "--out", str(tmp_path)),
        ],
        capture_output=True,
        text=True,
        timeout=600,
    )
    assert result.returncode == 0, result.stdout[-2000:] + result.stderr[-2000:]
    ray = json.loads((tmp_path / "metrics.json").read_text())
    expected = json.loads((local[2] / "metrics.json").read_text())
    # runs retried after a node crashed say something about the machine, not the brain
    retried = {
        "local": [c.pop("failed_runs_retried") for c in expected["conditions"]],
        "ray": [c.pop("failed_runs_retried") for c in ray["conditions"]],
    }
    assert ray.pop("command").startswith("toyroom eval") and expected.pop("command") == ""
    assert ray.pop("timing")["seconds"] > 0 and expected.pop("timing")["seconds"] > 0  # the machine's, too
    assert ray == expected, f"the Ray backend gave {ray}, the local one {expected} (retried runs: {retried})"


def test_brain_settings_reach_every_run(tmp_path: Path) -> None:
    """``toyroom eval --set ...`` hands the setting to each run's brain: the point model
    runs an episode; an unknown setting makes the brain refuse, so the episode fails."""
    point = evaluate(1, SEED, tmp_path / "point", brain_args=("--set", "belief_model=point"))
    (condition,) = point.conditions
    assert condition.numbers.episodes_failed == 0 and point.brain_args == ["--set", "belief_model=point"]
    belief_tv = condition.numbers.observers["btom"]["belief_tv"]
    assert isinstance(belief_tv, Interval) and belief_tv.mean is not None, belief_tv
    bad = evaluate(1, SEED, tmp_path / "bad", brain_args=("--set", "betta=1"))
    assert bad.conditions[0].numbers.episodes_failed == 1, (
        f"an unknown brain setting should fail the episode: {bad}"
    )
    logs = "".join(p.read_text() for p in (tmp_path / "bad").rglob("*.brain*.log"))
    assert "unknown setting 'betta'" in logs, logs[-2000:]


def test_episodes_generated_together_are_those_generated_one_by_one(tmp_path: Path) -> None:
    """One process writes a sweep's episodes (a process start is most of an episode's
    generation), the very files one call per episode writes."""
    rich_tasks = EpisodeSpec(Minds.RICH, EpisodeKind.TASKS, max_ticks=600)
    together = generate_all(tmp_path / "together", 4, seed=7, spec=rich_tasks)
    assert generate(tmp_path / "one", 3, 7, rich_tasks).read_text() == together[3].read_text()
    for index, path in enumerate(together):
        episode = ["--map", map_of(index), "--seed", str(7000 + index), "--out", str(tmp_path / f"a{index}")]
        options = ["--minds", "rich", "--kind", "tasks", "--max-ticks", "600"]
        made = subprocess.run(
            [sys.executable, "-m", "sim2d", "generate", *episode, *options],
            capture_output=True,
            text=True,
            check=True,
        )
        alone = Path(made.stdout.strip())
        assert path.name == alone.name, f"episode {index}: {path.name}, alone {alone.name}"
        assert path.read_text() == alone.read_text(), f"episode {index}: {path.name} differs made alone"
    bad = subprocess.run(
        [sys.executable, "-m", "sim2d", "generate", "--episodes", "paper:1", "attic:2", "--out", tmp_path],
        capture_output=True,
        text=True,
        check=False,
    )
    assert bad.returncode == 2 and "'attic:2' is not MAP:SEED" in bad.stderr, bad.stderr


def test_autonomy_settings_reach_every_episode_and_bad_ones_are_named(tmp_path: Path) -> None:
    """``toyroom eval --autonomy``: each generated episode carries the setting; a setting the
    generator refuses is a ``ValueError`` in its words before any run starts."""
    spec = EpisodeSpec(kind=EpisodeKind.TASKS, max_ticks=300, autonomy=("replan_lag=[9000, 9000]",))
    paths = generate_all(tmp_path, 2, seed=3, spec=spec)
    for path in paths:
        assert "replan_lag = [9000, 9000]" in path.read_text(), path.read_text()[:400]
    check_autonomy(["replan_lag=[9000, 9000]"])
    with pytest.raises(ValueError, match=r"miss = 2\.0"):
        check_autonomy(["miss=2"])
    with pytest.raises(ValueError, match="NAME=VALUE"):
        Condition(autonomy=("miss",))
