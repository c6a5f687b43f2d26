"""``toyroom eval --days N --batch K``: a household's chain days on one engine and one brain
process (``python -m brain --serve``, :mod:`toyroom.evaluation.dayserver`) score as a process
pair a day does (``--batch 1``): the same ``metrics.json`` but timing, and the same memory;
a brain killed mid-day in a batch has its day run again alone, and the days after it are
as they were. Real ``toyroom eval`` processes."""

from __future__ import annotations

import json
import re
import shutil
import subprocess
import sys
import tempfile
import threading
import time
from pathlib import Path
from typing import Any

import psutil
import pytest

from brain.__main__ import run_parser, served_args
from brain.errors import BrainError

HOUSEHOLD = ["--episodes", "1", "--seed", "3", "--kind", "tasks", "--max-ticks", "100", "--workers", "1"]
OPERATIONAL = ("timing", "command", "failed_runs_retried")
"""What may differ between two runs of the same evaluation (as in test_households_resume)."""


def _start(out: Path, *extra: str) -> subprocess.Popen[str]:
    command = [sys.executable, "-m", "toyroom", "eval", *HOUSEHOLD, *extra, "--out", str(out)]
    return subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)


def _finish(process: subprocess.Popen[str]) -> None:
    _, err = process.communicate(timeout=500)
    assert process.returncode == 0, f"expected exit 0, got {process.returncode}:\n{err[-3000:]}"


def _flat(value: Any, path: str = "") -> dict[str, Any]:
    """``metrics.json`` but :data:`OPERATIONAL`, as ``{path: value}``."""
    if isinstance(value, dict):
        items = [(k, v) for k, v in value.items() if k not in OPERATIONAL]
        return {p: x for k, v in items for p, x in _flat(v, f"{path}/{k}").items()}
    if isinstance(value, list):
        return {p: x for i, v in enumerate(value) for p, x in _flat(v, f"{path}[{i}]").items()}
    return {path: value}


def _differences(a: Path, b: Path) -> list[str]:
    one, two = (_flat(json.loads((out / "metrics.json").read_text())) for out in (a, b))
    keys = sorted(one.keys() | two.keys())
    return [f"{k}: {one.get(k)} != {two.get(k)}" for k in keys if one.get(k) != two.get(k)][:10]


def _memory(out: Path, chain: str) -> str:
    """``toyroom memory show`` of a chain's memory file, its path and clock times left out.
    The file is shown from a copy at a short path: ``show`` draws at 160 columns, and the
    title line naming a long pytest path wraps into the table (CI at 7f13c30)."""
    (path,) = out.glob(f"work/*/household-0/memory/{chain}.sqlite")
    with tempfile.TemporaryDirectory(prefix="m") as folder:
        copy = Path(shutil.copy(path, Path(folder) / "memory.sqlite"))
        shown = subprocess.run(
            [sys.executable, "-m", "toyroom", "memory", "show", str(copy)],
            capture_output=True,
            text=True,
            timeout=60,
        )
    assert shown.returncode == 0, shown.stderr
    shown.stdout = shown.stdout.replace(str(copy), "FILE")
    return re.sub(r"\d\d-\d\d \d\d:\d\d", "MM-DD hh:mm", "\n".join(shown.stdout.splitlines()[1:]))


@pytest.mark.sweep  # two households evaluations of four chains each: a minute on two cores
@pytest.mark.timeout(900)
def test_a_households_days_on_one_engine_and_brain_score_as_a_process_pair_a_day(tmp_path: Path) -> None:
    alone, batched = tmp_path / "alone", tmp_path / "batched"
    first = _start(alone, "--days", "2", "--policies", "tom", "--batch", "1")
    try:
        second = _start(batched, "--days", "2", "--policies", "tom", "--batch", "4")
        _finish(second)
        _finish(first)
    finally:
        for process in (first, locals().get("second")):
            if process is not None and process.poll() is None:
                process.kill()
                process.wait()
    differing = _differences(alone, batched)
    assert not differing, "expected --batch 1's metrics, got:\n" + "\n".join(differing)
    for chain in ("observe", "tom"):
        assert _memory(alone, chain) == _memory(batched, chain), f"{chain}'s memory differs"
    logs = batched / "work" / "omniscient-simple-tasks" / "household-0" / "logs"
    served = (logs / "days.brain.log").exists() and not list(logs.rglob("*-d1-*.brain.log"))
    assert served, f"expected one log for the household's brains: {sorted(logs.rglob('*.log'))}"
    minds = list(logs.glob("observe/*-d?-btom-observe.shadows/minds-btom.jsonl.gz"))
    assert len(minds) == 2, sorted(logs.rglob("*"))


def test_a_serving_brain_takes_each_run_as_a_json_list_of_options() -> None:
    """``python -m brain --serve``: each line of its input a run's options, as a JSON list; a
    line that is not, or one that asks to serve again, is refused in one line."""
    parser = run_parser()
    args = served_args(parser, '["--scenario", "a b/gen-d1.toml", "--robot", "act"]\n')
    assert (args.scenario, args.robot, args.serve) == ("a b/gen-d1.toml", "act", False), args
    with pytest.raises(BrainError, match="--serve: a line of input is not JSON"):
        served_args(parser, "--scenario gen-d1.toml\n")
    with pytest.raises(BrainError, match="--serve: a line of input is not a JSON list of options"):
        served_args(parser, '{"scenario": "gen-d1.toml"}\n')
    with pytest.raises(BrainError, match="--serve: a run's options cannot ask to serve again"):
        served_args(parser, '["--serve"]\n')


def _kill_on_day_two(stop: threading.Event, evaluation: int, work: Path, killed: list[int]) -> None:
    """SIGKILL the serving brain of the evaluation of pid ``evaluation`` (its files in ``work``)
    once the observing chain has begun day 2 (its run log of the day holds a state; the day, or
    the next run, is cut off)."""
    while not stop.is_set() and not killed:
        begun = list(work.glob("*/household-0/logs/observe/*-d2-btom-observe.shadows/inputs.jsonl"))
        if not begun or begun[0].stat().st_size == 0:
            time.sleep(0.02)
            continue
        for process in psutil.process_iter(["pid", "cmdline"]):
            command = " ".join(process.info["cmdline"] or [])
            try:
                ours = evaluation in {p.pid for p in process.parents()}
            except psutil.NoSuchProcess:
                continue
            if ours and "-m brain" in command and "--serve" in command:
                try:
                    process.kill()
                    killed.append(process.info["pid"])
                except psutil.NoSuchProcess:
                    pass
                break


@pytest.mark.sweep  # two households evaluations of three days, one with a kill: over a minute
@pytest.mark.timeout(900)
def test_a_batch_brain_killed_mid_day_has_the_day_run_alone(tmp_path: Path) -> None:
    whole, broken = tmp_path / "whole", tmp_path / "broken"
    first = _start(whole, "--days", "3", "--policies", "none", "--batch", "6")
    stop, killed = threading.Event(), []
    watcher = None
    try:
        second = _start(broken, "--days", "3", "--policies", "none", "--batch", "6")
        watched = (stop, second.pid, broken / "work", killed)
        watcher = threading.Thread(target=_kill_on_day_two, args=watched, daemon=True)
        watcher.start()
        _finish(second)
        _finish(first)
    finally:
        stop.set()
        if watcher is not None:
            watcher.join(timeout=10)
        for process in (first, locals().get("second")):
            if process is not None and process.poll() is None:
                process.kill()
                process.wait()
    assert killed, "no serving brain was found to kill on day 2"
    (records,) = json.loads((broken / "episodes.json").read_text()).values()
    said = [line for record in records for line in record.get("failed_runs") or []]
    assert any("its batch of days did not finish it" in line for line in said), f"the kill: {said}"
    differing = _differences(whole, broken)
    assert not differing, "expected the uninterrupted run's metrics:\n" + "\n".join(differing)
