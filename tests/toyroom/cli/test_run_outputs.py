"""``toyroom run --out DIR``: bad settings are refused before any process starts, a finished
run replaces an earlier one in ``DIR`` whole (and nothing else there), and a run that does not
finish never mixes with an earlier one: its outputs are marked ``FAILED``, beside ``DIR``."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import psutil
import pytest


def toyroom_run(out: Path, *args: str, timeout: float = 300) -> subprocess.CompletedProcess[str]:
    """``toyroom run --out OUT ARGS`` as a real process, to its end."""
    return subprocess.run(
        [sys.executable, "-m", "toyroom", "run", "--out", str(out), "--no-live", *args],
        capture_output=True,
        text=True,
        timeout=timeout,
        check=False,
    )


def snapshot(folder: Path) -> dict[str, bytes]:
    """Every file under ``folder`` (relative path: contents)."""
    return {str(p.relative_to(folder)): p.read_bytes() for p in sorted(folder.rglob("*")) if p.is_file()}


def earlier_run(folder: Path, *extra: str) -> dict[str, bytes]:
    """A folder that looks like an earlier run's outputs (and ``extra`` files); its snapshot."""
    folder.mkdir(parents=True)
    for name in ("engine.log", "brain.log", "trace.jsonl", "mind.csv", "report.md", "beliefs.png", *extra):
        (folder / name).parent.mkdir(parents=True, exist_ok=True)
        (folder / name).write_text(f"earlier {name}\n")
    return snapshot(folder)


@pytest.mark.parametrize(
    ("args", "message"),
    [
        (("--set", "beta=abc"), "model.beta: expected float, got 'abc'"),
        (("--set", "beta=-3"), "beta=-3.0 (allowed: beta >= 0)"),
        (("--set", "attempts=0"), "attempts=0 (allowed: an int >= 1)"),
        (("--settings", "{tmp}/bad.toml"), "hazard=2.0 (allowed: 0 <= hazard < 1)"),
    ],
    ids=["type", "range", "robot", "file"],
)
def test_bad_settings_are_refused_before_any_process_starts(
    tmp_path: Path, args: tuple[str, ...], message: str
) -> None:
    (tmp_path / "bad.toml").write_text("[model]\nhazard = 2\n")
    out = tmp_path / "out"
    before = earlier_run(out)
    result = toyroom_run(out, "--scenario", "sally-anne", *(a.format(tmp=tmp_path) for a in args))
    assert result.returncode == 2, f"exit status {result.returncode}:\n{result.stdout}\n{result.stderr}"
    assert message in result.stderr, result.stderr
    assert "results in" not in result.stdout, result.stdout
    assert snapshot(out) == before, "the earlier run's folder was written to"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["bad.toml", "out"], "a run's folder was made"


def engine_fails_at_start(folder: Path) -> Path:
    """A scenario the loader accepts but whose engine fails at its start, before the
    handshake: paper-auto's people act by the brain's planner, and no planner table is given."""
    scenarios = Path(__file__).resolve().parents[3] / "sim2d" / "scenarios"
    (folder / "paper.map.toml").write_text((scenarios / "paper.map.toml").read_text())
    text = (scenarios / "paper-auto.toml").read_text()
    assert "[autonomy]\n" in text, "paper-auto lost its [autonomy] table: update this test"
    (folder / "planned.toml").write_text(text.replace("[autonomy]\n", '[autonomy]\nplanner = "model"\n'))
    return folder / "planned.toml"


def test_a_missing_scenario_is_refused_before_anything_starts(tmp_path: Path) -> None:
    out = tmp_path / "out"
    before = earlier_run(out)
    result = toyroom_run(out, "--scenario", "no-such-scenario")
    lines = result.stderr.strip().splitlines()
    assert result.returncode == 2 and len(lines) == 1 and "no-such-scenario" in lines[0], (
        f"expected exit 2 and one line naming the scenario, got {result.returncode}:\n{result.stderr}"
    )
    assert snapshot(out) == before and sorted(p.name for p in tmp_path.iterdir()) == ["out"]


def test_a_failed_run_leaves_the_earlier_run_as_it_was(tmp_path: Path) -> None:
    out = tmp_path / "out"
    before = earlier_run(out)
    result = toyroom_run(out, "--scenario", str(engine_fails_at_start(tmp_path)))
    assert result.returncode == 1, f"exit status {result.returncode}:\n{result.stderr}"
    assert "results in" not in result.stdout, result.stdout
    assert snapshot(out) == before, "the failed run mixed with the earlier one"
    [failed] = [p for p in tmp_path.iterdir() if p.name.startswith("out.failed-")]
    note = (failed / "FAILED").read_text()
    assert "the engine exited with status 2 before it answered the handshake" in note, note
    assert 'planner = "model"' in (failed / "engine.log").read_text()
    assert f"see {failed / 'FAILED'}" in result.stderr, result.stderr


def test_a_failed_run_into_a_new_folder_is_marked_there(tmp_path: Path) -> None:
    out = tmp_path / "new" / "out"
    scenario = engine_fails_at_start(tmp_path)
    result = toyroom_run(out, "--scenario", str(scenario))
    assert result.returncode == 1, result.stderr
    assert "the engine exited with status 2" in (out / "FAILED").read_text()
    assert sorted(p.name for p in out.parent.iterdir()) == ["out"]


@pytest.mark.parametrize("others", [False, True], ids=["only-a-run", "with-other-things"])
def test_a_finished_run_replaces_the_earlier_run_whole(tmp_path: Path, others: bool) -> None:
    """Whatever the earlier run wrote goes (also files this run does not write); other things
    in the folder, such as another run's sub-folder, stay."""
    out = tmp_path / "out"
    earlier_run(out, "minds-perceptonly.jsonl", "FAILED", *(["paper-1/mind.csv"] if others else []))
    result = toyroom_run(out, "--scenario", "sally-anne", "--robot", "observe")
    assert result.returncode == 0, result.stderr
    assert f"results in {out}/" in result.stdout, result.stdout
    assert not (out / "minds-perceptonly.jsonl").exists(), "the earlier run's shadow minds are still there"
    assert not (out / "FAILED").exists()
    assert (out / "mind.csv").read_text().startswith("tick,"), "the earlier mind.csv is still there"
    assert (out / "report.md").read_text() != "earlier report.md\n"
    if others:
        assert (out / "paper-1" / "mind.csv").read_text() == "earlier paper-1/mind.csv\n"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["out"], "a folder was left beside it"


def test_a_project_folder_is_not_taken_for_an_earlier_run(tmp_path: Path) -> None:
    (tmp_path / "settings.toml").write_text("[model]\nbeta = 3\n")
    (tmp_path / "notes.md").write_text("mine\n")
    before = snapshot(tmp_path)
    result = toyroom_run(tmp_path, "--scenario", "sally-anne")
    assert result.returncode == 2, result.stderr
    assert "holds settings.toml but no earlier run" in result.stderr, result.stderr
    assert snapshot(tmp_path) == before


def test_a_run_killed_outright_leaves_its_folder_marked(tmp_path: Path, world: str) -> None:
    """SIGKILL gives the run no chance to say why: its folder says so from the start."""
    out = tmp_path / "out"
    with tempfile.TemporaryFile() as log:
        command = [sys.executable, "-m", "toyroom", "run", "--scenario", "paper-robot", "--out", str(out)]
        process = subprocess.Popen([*command, "--no-live", "--world", world], stdout=log, stderr=log)
        nodes: list[psutil.Process] = []
        try:
            deadline = time.monotonic() + 120
            while not (staging := list(tmp_path.glob("out.running-*/engine.log"))):
                assert process.poll() is None and time.monotonic() < deadline, "no run folder appeared"
                time.sleep(0.02)
            nodes = psutil.Process(process.pid).children(recursive=True)
            os.kill(process.pid, signal.SIGKILL)
            process.wait(timeout=30)
            _, alive = psutil.wait_procs(nodes, timeout=30)
            assert not alive, (
                f"nodes still running 30 s after the run was killed: {[p.cmdline()[:4] for p in alive]}"
            )
        finally:
            for node in [*nodes, *([psutil.Process(process.pid)] if process.poll() is None else [])]:
                try:
                    node.kill()
                except psutil.NoSuchProcess:
                    pass
    folder = staging[0].parent
    assert folder.name == f"out.running-{process.pid}"
    note = (folder / "FAILED").read_text()
    assert f"process {process.pid}" in note and "killed" in note, note
    assert f"toyroom infer {folder / 'trace.jsonl'} --out {folder}" in note, note


def test_eval_refuses_bad_settings_before_any_episode(tmp_path: Path) -> None:
    result = subprocess.run(
        [
            sys.executable,
            "-m",
            "toyroom",
            "eval",
            "--episodes",
            "1",
            "--set",
            "hazard=-1",
            "--out",
            str(tmp_path / "e"),
        ],
        capture_output=True,
        text=True,
        timeout=300,
        check=False,
    )
    assert result.returncode == 2, result.stderr
    assert "hazard=-1.0 (allowed: 0 <= hazard < 1)" in result.stderr, result.stderr
    assert not (tmp_path / "e").exists(), "an episode ran"
