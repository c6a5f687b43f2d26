"""``toyroom eval --days N`` stopped by Ctrl-C and run again: the finished chain days are kept
in ``episodes.jsonl`` as each finishes, the same command resumes every chain from its last
finished day's morning and memory file, and ``metrics.json`` is the uninterrupted run's; its
progress counts household days; its ``work/`` folder is pruned once finished. Real ``toyroom
eval`` processes, a real SIGINT."""

from __future__ import annotations

import json
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from toyroom.bench.households import scores

DAYS = [
    *("--days", "3", "--episodes", "2", "--seed", "3", "--kind", "tasks"),
    *("--max-ticks", "120", "--workers", "2", "--policies", "none"),
]
CHAIN_DAYS = 2 * 3 * 2  # households x days x chains (observe, observe-fresh)


def _command(out: Path) -> list[str]:
    return [sys.executable, "-m", "toyroom", "eval", *DAYS, "--out", str(out)]


def _lines(path: Path) -> int:
    return len(path.read_text().splitlines()) if path.exists() else 0


def _differences(a: Path, b: Path) -> list[str]:
    """The paths of ``metrics.json`` whose values differ, ``path: A != B`` (the first ten)."""
    one, two = scores(a), scores(b)
    return [
        f"{k}: {one.get(k)} != {two.get(k)}"
        for k in sorted(one.keys() | two.keys())
        if one.get(k) != two.get(k)
    ][:10]


def _work_files(out: Path) -> list[Path]:
    """The files under ``out/work`` but a failed attempt's logs (``*.failedN.log``): a loaded
    machine retries a run now and then, and keeps the failure's log (CI at d1eeb9f did)."""
    work = out / "work"
    return sorted(p.relative_to(work) for p in work.rglob("*") if p.is_file() and ".failed" not in p.name)


def _stop_after(process: subprocess.Popen[str], jsonl: Path, days: int, deadline_s: float) -> None:
    """SIGINT ``process`` once ``jsonl`` holds ``days`` finished chain days (or it ended)."""
    deadline = time.monotonic() + deadline_s
    while process.poll() is None and _lines(jsonl) < days and time.monotonic() < deadline:
        time.sleep(0.05)  # polling the event (a line appended), not waiting out a guess
    assert process.poll() is None, f"the evaluation ended before {days} chain days were kept"
    assert _lines(jsonl) >= days, f"expected {days} chain days within {deadline_s} s, got {_lines(jsonl)}"
    process.send_signal(signal.SIGINT)


@pytest.mark.sweep  # two households evaluations of three days end to end, one stopped: over a minute
@pytest.mark.timeout(600)
def test_a_households_evaluation_stopped_by_ctrl_c_resumes_to_the_same_metrics(tmp_path: Path) -> None:
    whole_out, part_out = tmp_path / "whole", tmp_path / "part"
    whole = subprocess.Popen(_command(whole_out), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        part = subprocess.Popen(_command(part_out), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        _stop_after(part, part_out / "episodes.jsonl", 3, 300)
        _, stopped = part.communicate(timeout=60)
        assert part.returncode == 130, (
            f"expected exit 130 on SIGINT, got {part.returncode}:\n{stopped[-2000:]}"
        )
        assert f"chain days in {part_out / 'episodes.jsonl'}" in stopped, stopped[-2000:]
        assert (part_out / "unfinished-eval.json").exists() and not (part_out / "metrics.json").exists()
        kept = _lines(part_out / "episodes.jsonl")
        assert 3 <= kept < CHAIN_DAYS, f"expected some of {CHAIN_DAYS} chain days kept, got {kept}"
        again = subprocess.run(_command(part_out), capture_output=True, text=True, timeout=400)
        said = again.stdout + again.stderr
        assert again.returncode == 0, f"expected exit 0 resuming, got {again.returncode}:\n{said[-3000:]}"
        resumed = f"resuming the unfinished evaluation in {part_out}: {kept} of {CHAIN_DAYS} chain days kept"
        assert resumed in " ".join(said.split()), f"expected {resumed!r}, got:\n{said[-3000:]}"
        assert "6/6 household days" in said, (
            f"expected the progress to count 6/6 household days:\n{said[-2000:]}"
        )
        _, whole_err = whole.communicate(timeout=400)
    finally:
        for process in (whole, locals().get("part")):
            if process is not None and process.poll() is None:
                process.kill()
                process.wait()
    assert whole.returncode == 0, whole_err[-3000:]
    total = _lines(part_out / "episodes.jsonl")
    assert total == CHAIN_DAYS, f"expected each chain day kept once ({CHAIN_DAYS}), got {total} lines"
    differing = _differences(whole_out, part_out)
    assert not differing, "expected the uninterrupted run's metrics, got:\n" + "\n".join(differing)
    assert not list((part_out / "work").rglob("inputs.jsonl")), "a finished evaluation kept the runs' inputs"
    minds = list((part_out / "work").rglob("minds-btom.jsonl.gz"))
    assert len(minds) == CHAIN_DAYS, f"expected the observing chains' minds gzipped, got {len(minds)} files"


def test_another_days_is_another_plan() -> None:
    """An unfinished households evaluation is resumed only by the same ``--days``."""
    from toyroom.evaluation.conditions import Condition
    from toyroom.evaluation.resume import differences, plan_of

    three, four = (plan_of(2, 3, [Condition()], [], [], False, 120, days) for days in (3, 4))
    assert differences(three, four) == ["--days: 3, now 4"], differences(three, four)


@pytest.mark.sweep  # Ray started in the driver twice over: two minutes and more
@pytest.mark.timeout(900)
def test_a_households_evaluation_stopped_here_finishes_on_ray_to_the_same_metrics(tmp_path: Path) -> None:
    """Stopped mid-household on the local backend, resumed with ``--backend ray``: the Ray
    task of a household gets its finished chain days, scenarios, mornings and memory files by
    value and goes on from there; the metrics are the uninterrupted local run's."""
    whole_out, part_out = tmp_path / "whole", tmp_path / "part"
    whole = subprocess.Popen(_command(whole_out), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    part = None
    try:
        part = subprocess.Popen(_command(part_out), stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        _stop_after(part, part_out / "episodes.jsonl", 3, 300)
        _, stopped = part.communicate(timeout=60)
        assert part.returncode == 130, (
            f"expected exit 130 on SIGINT, got {part.returncode}:\n{stopped[-2000:]}"
        )
        on_ray = [*_command(part_out), "--backend", "ray"]
        again = subprocess.run(on_ray, capture_output=True, text=True, timeout=600)
        said = again.stdout + again.stderr
        assert again.returncode == 0, (
            f"expected exit 0 resuming on Ray, got {again.returncode}:\n{said[-3000:]}"
        )
        _, whole_err = whole.communicate(timeout=600)
    finally:
        for process in (whole, part):
            if process is not None and process.poll() is None:
                process.kill()
                process.wait()
    assert whole.returncode == 0, whole_err[-3000:]
    total = _lines(part_out / "episodes.jsonl")
    assert total == CHAIN_DAYS, f"expected each chain day kept once ({CHAIN_DAYS}), got {total} lines"
    differing = _differences(whole_out, part_out)
    assert not differing, "expected the local run's metrics on Ray, got:\n" + "\n".join(differing)
    (records,) = json.loads((part_out / "episodes.json").read_text()).values()
    assert all(r.get("node") for r in records), (
        f"expected each day's Ray node, got {[r.get('node') for r in records]}"
    )
    kept, local = _work_files(part_out), _work_files(whole_out)
    differing = sorted(set(kept) ^ set(local))
    assert kept == local, f"expected the local run's work/ files, got {differing} differing"
