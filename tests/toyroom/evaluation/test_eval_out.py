"""``toyroom eval --out DIR`` over an earlier evaluation (issue 64, item 9): a finished one is
refused before anything starts, one line and exit 2, as ``toyroom run`` refuses a folder it
would spoil (a 2-episode evaluation used to replace a 6-episode one silently, exit 0), unless
``--fresh``, which removes the earlier evaluation's outputs (and only those) first; and a
finished evaluation's scratch folder keeps only its node logs and scenarios, so scratch
folders no longer pile up (3 of them, 164 MB). Real processes: the evaluator, its engines and
brains over loopback Zenoh."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from toyroom.evaluation.folder import check_out, clear, finished_evaluation, prune_scratch
from toyroom.evaluation.resume import IncompatibleRun

SMALL = ("--seed", "3", "--max-ticks", "100", "--policies", "none", "--workers", "1", "--batch", "1")


def _eval(out: Path, episodes: int, *extra: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [
            sys.executable,
            "-m",
            "toyroom",
            "eval",
            "--episodes",
            str(episodes),
            *SMALL,
            "--out",
            str(out),
            *extra,
        ],
        capture_output=True,
        text=True,
        timeout=600,
    )


@pytest.mark.sweep  # three evaluations end to end: most of a minute (make test's budget)
def test_a_finished_evaluation_is_refused_and_fresh_replaces_it(tmp_path: Path) -> None:
    out = tmp_path / "e"
    first = _eval(out, 2)
    assert first.returncode == 0, first.stderr[-2000:]
    metrics = (out / "metrics.json").read_bytes()
    scratch = list(out.glob("toyroom-eval-*"))
    assert len(scratch) == 1, f"expected one scratch folder, got {scratch}"
    left = sorted(
        p.name for p in scratch[0].rglob("*") if p.is_file() and not p.name.endswith((".log", ".toml"))
    )
    assert left == [], f"expected a finished evaluation's scratch to keep only logs and scenarios, got {left}"
    assert list(scratch[0].rglob("*.brain.log")), (
        "the node logs (a failed episode's reader goes there) went too"
    )

    again = _eval(out, 1)
    said = (
        f"toyroom eval: --out {out} holds a finished evaluation (2 episodes x 1 condition): run with "
        "--fresh to replace it, or choose another --out"
    )
    lines = again.stderr.strip().splitlines()
    assert (again.returncode, lines) == (2, [said]), (
        f"expected exit 2 and the one line {said!r}, got exit {again.returncode} and:\n{again.stderr}"
    )
    assert (out / "metrics.json").read_bytes() == metrics, "the refused evaluation changed metrics.json"

    (out / "notes.txt").write_text("mine\n")  # not the evaluation's: --fresh leaves it
    (out / "toyroom-eval-stale").mkdir()  # an older evaluation's scratch: --fresh removes it
    fresh = _eval(out, 1, "--fresh")
    assert fresh.returncode == 0, fresh.stderr[-2000:]
    assert json.loads((out / "metrics.json").read_text())["episodes"] == 1, "--fresh did not replace it"
    assert (out / "notes.txt").read_text() == "mine\n", "--fresh removed a file that was not the evaluation's"
    folders = sorted(p.name for p in out.glob("toyroom-eval-*"))
    assert len(folders) == 1 and folders != ["toyroom-eval-stale"], (
        f"expected one new scratch folder, got {folders}"
    )


def test_an_unfinished_evaluation_is_not_a_finished_one(tmp_path: Path) -> None:
    (tmp_path / "metrics.json").write_text('{"episodes": 6, "conditions": [{}, {}]}')
    assert finished_evaluation(tmp_path) == "a finished evaluation (6 episodes x 2 conditions)"
    (tmp_path / "unfinished-eval.json").write_text("{}")
    assert finished_evaluation(tmp_path) is None, (
        "an unfinished evaluation (resumed) was taken for a finished one"
    )
    check_out(tmp_path, fresh=False)  # resumed or refused later, by what it is of


def test_fresh_removes_only_the_evaluations_outputs(tmp_path: Path) -> None:
    (tmp_path / "recordings").mkdir()
    clear(tmp_path)  # no evaluation here: someone else's recordings stay
    assert (tmp_path / "recordings").is_dir(), "--fresh removed a folder of a folder holding no evaluation"
    (tmp_path / "recordings").rmdir()
    names = ["metrics.json", "episodes.json", "episodes.jsonl", "report.md", "metrics-a.png", "days-a.png"]
    for name in [*names, "unfinished-eval.json", "mine.csv", ".metrics.partial-1-2.json"]:
        (tmp_path / name).write_text("x")
    for folder in ("recordings", "toyroom-eval-abc", "work", "paper-1"):
        (tmp_path / folder).mkdir()
        (tmp_path / folder / "f").write_text("x")
    clear(tmp_path)
    assert sorted(p.name for p in tmp_path.iterdir()) == ["mine.csv", "paper-1"]


def test_a_finished_evaluation_without_fresh_is_refused_naming_it(tmp_path: Path) -> None:
    (tmp_path / "metrics.json").write_text('{"households": 2, "days": 3, "conditions": [{}]}')
    try:
        check_out(tmp_path, fresh=False)
    except IncompatibleRun as err:
        assert "holds a finished evaluation (2 households x 1 condition)" in str(err), str(err)
    else:
        raise AssertionError("a finished evaluation in --out was not refused")
    check_out(tmp_path, fresh=True)
    assert list(tmp_path.iterdir()) == [], "--fresh kept the finished evaluation"


def test_pruning_keeps_the_logs_and_scenarios(tmp_path: Path) -> None:
    logs = tmp_path / "c" / "logs"
    (logs / "x-btom-observe.shadows").mkdir(parents=True)
    (tmp_path / "c" / "scenarios").mkdir()
    (tmp_path / "c" / "policies").mkdir()
    for path in (
        logs / "x.engine.log",
        logs / "x.brain.failed1.log",
        logs / "x-btom-observe.shadows" / "minds-btom.jsonl",
        logs / "x-btom-observe.shadows" / "inputs.jsonl",
        tmp_path / "c" / "scenarios" / "gen-paper-s1.toml",
        tmp_path / "c" / "policies" / "p.npz",
    ):
        path.write_text("x")
    prune_scratch(tmp_path)
    kept = sorted(str(p.relative_to(tmp_path)) for p in tmp_path.rglob("*"))
    assert kept == [
        "c",
        "c/logs",
        "c/logs/x.brain.failed1.log",
        "c/logs/x.engine.log",
        "c/scenarios",
        "c/scenarios/gen-paper-s1.toml",
    ], kept
