"""Bad arguments are one line naming what is wrong and exit 2, never a traceback; an
evaluation whose every episode failed exits 1 and says so, one where some failed says how
many (issue 49, item 7). Real ``toyroom`` processes."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from msgspec.structs import replace

from toyroom.evaluation import Condition, aggregate
from toyroom.evaluation.summary import ConditionSummary, Evaluation

CASES = [
    (("eval", "--episodes", "0", "--out", "{tmp}/e"), "toyroom eval: --episodes must be at least 1, got 0"),
    (("eval", "--episodes", "-2", "--out", "{tmp}/e"), "toyroom eval: --episodes must be at least 1, got -2"),
    (("eval", "--workers", "0", "--out", "{tmp}/e"), "toyroom eval: --workers must be at least 1, got 0"),
    (
        ("eval", "--max-ticks", "-1", "--out", "{tmp}/e"),
        "toyroom eval: --max-ticks must be at least 1, got -1",
    ),
    (
        ("eval", "--days", "2", "--batch", "0", "--out", "{tmp}/e"),
        "toyroom eval: --batch must be at least 1, got 0",
    ),
    (
        ("eval", "--days", "100", "--out", "{tmp}/e"),
        "toyroom eval: --days is a household's days, 1 to 99, got 100",
    ),
    (
        ("fit", "{tmp}/run.mcap", "--params", "beta", "--out", "{tmp}/afile"),
        "toyroom fit: --out {tmp}/afile: expected a folder, got a file",
    ),
    (
        ("generate", "--map", "paper", "--seed", "1", "--out", "{tmp}/afile"),
        "toyroom generate: --out {tmp}/afile: expected a folder, got a file",
    ),
    (
        ("export-scenario", "--scenario", "sally-anne", "--out", "{tmp}/adir"),
        "toyroom export-scenario: --out {tmp}/adir: expected a file, got a folder",
    ),
    (
        ("run", "--scenario", "sally-anne", "--no-live", "--out", "{tmp}/r", "--record", "{tmp}/adir"),
        "toyroom run: --record {tmp}/adir: expected a file, got a folder",
    ),
    (
        ("run", "--scenario", "sally-anne", "--no-live", "--out", "{tmp}/r", "--record", "{tmp}/no/run.mcap"),
        "toyroom run: --record {tmp}/no/run.mcap: the folder {tmp}/no does not exist",
    ),
    (("record", "{tmp}/adir"), "toyroom record: {tmp}/adir: expected a file, got a folder"),
    *(
        (
            ("replay", "{tmp}/run.mcap", "--speed", speed),
            f"toyroom replay: --speed {shown}: expected 0 (as fast as possible) or a number of times "
            "real time from 0.001",
        )
        for speed, shown in (("1e-300", "1e-300"), ("-1", "-1.0"), ("nan", "nan"))
    ),
]


@pytest.mark.parametrize(
    ("argv", "expected"), CASES, ids=lambda c: " ".join(c) if isinstance(c, tuple) else ""
)
def test_a_bad_argument_is_one_line_and_exit_2(tmp_path: Path, argv: tuple[str, ...], expected: str) -> None:
    (tmp_path / "afile").write_text("a file\n")
    (tmp_path / "adir").mkdir()
    args = [a.format(tmp=tmp_path) for a in argv]
    result = subprocess.run(
        [sys.executable, "-m", "toyroom", *args], capture_output=True, text=True, timeout=120
    )
    lines = result.stderr.strip().splitlines()
    want = expected.format(tmp=tmp_path)
    assert (result.returncode, lines) == (2, [want]), (
        f"expected exit 2 and the one line {want!r}, got exit {result.returncode} and:\n{result.stderr}"
    )
    assert sorted(p.name for p in tmp_path.iterdir()) == ["adir", "afile"], (
        "a refused command wrote something"
    )


@pytest.mark.parametrize("lease", ["5", "1e9", "soon"])
def test_a_lease_out_of_range_is_refused_by_argparse(tmp_path: Path, lease: str) -> None:
    """``--lease-ms`` (argparse's usage, then one line naming the value; exit 2)."""
    out = tmp_path / "r"
    argv = ["run", "--scenario", "sally-anne", "--no-live", "--out", str(out), "--lease-ms", lease]
    result = subprocess.run(
        [sys.executable, "-m", "toyroom", *argv], capture_output=True, text=True, timeout=120
    )
    last = result.stderr.strip().splitlines()[-1]
    assert result.returncode == 2 and last.startswith("toyroom run: error: argument --lease-ms: "), (
        f"expected exit 2 and argparse's line on --lease-ms, got exit {result.returncode}:\n{result.stderr}"
    )
    assert repr(lease) in last or f"{lease} is outside 100-60000 ms" in last, last
    assert not out.exists(), "a refused run wrote its folder"


@pytest.mark.parametrize(("tick", "shown"), [("-5", "-5"), ("soon", "'soon'")])
def test_a_replay_to_a_tick_before_the_first_is_refused(tmp_path: Path, tick: str, shown: str) -> None:
    """``--until-tick -5`` sent nothing and exited 0; now argparse refuses it (exit 2, one line
    naming the value)."""
    argv = ["replay", str(tmp_path / "run.mcap"), "--until-tick", tick]
    result = subprocess.run(
        [sys.executable, "-m", "toyroom", *argv], capture_output=True, text=True, timeout=120
    )
    last = result.stderr.strip().splitlines()[-1]
    expected = f"toyroom replay: error: argument --until-tick: expected a whole number >= 0, got {shown}"
    assert (result.returncode, last) == (2, expected), (
        f"expected exit 2 and {expected!r}, got exit {result.returncode}:\n{result.stderr}"
    )


def _metrics(failed: list[int], episodes: int) -> Evaluation:
    """An evaluation of ``episodes`` per condition, ``failed`` of them failed in each."""
    nothing = aggregate([], 1, ("btom",))
    conditions = [
        ConditionSummary(condition=Condition(), numbers=replace(nothing, episodes_failed=n), by_map={})
        for n in failed
    ]
    return Evaluation(
        episodes=episodes, seed=1, brain_args=[], policies=[], command="", timing={}, conditions=conditions
    )


def test_the_terminal_says_how_many_episodes_failed(capsys: pytest.CaptureFixture[str]) -> None:
    from toyroom.cli.commands.eval import failed_episodes

    assert failed_episodes(_metrics([0, 0], 4), Path("e")) == 0
    assert capsys.readouterr().err == "", "nothing to say when every episode was scored"
    assert failed_episodes(_metrics([1, 2], 4), Path("e")) == 0, "some failed: the others are scored"
    said = capsys.readouterr().err
    assert said.startswith("toyroom eval: 3 of 8 episodes failed; the metrics are over the other 5 ("), said


def test_an_evaluation_whose_every_episode_failed_exits_1(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    """An unknown brain setting (past the CLI's check, as from a settings file the brain
    refuses) fails every run, so every episode: exit 1, and the terminal says so."""
    from toyroom.cli.commands.eval import eval_main

    code = eval_main(1, 5, 1, "local", tmp_path / "e", ("--set", "betta=1"), max_ticks=30, batch=1)
    err = capsys.readouterr().err
    assert code == 1, f"expected exit 1 when every episode failed, got {code}:\n{err[-2000:]}"
    assert (
        f"toyroom eval: every episode failed (1 of 1), nothing scored (their errors are in {tmp_path / 'e'}"
        in err
    ), err
