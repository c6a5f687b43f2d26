"""A full disk while ``toyroom eval``, ``infer`` and ``fit`` write their outputs (issue 64, item
11): one line naming the file and why (exit 1), as ``toyroom run`` says it, and no half-written
file (each is written to a temporary file, then renamed: :mod:`bridge.recording.atomic`). It
used to be a traceback (``OSError: [Errno 28]``), a 0-byte ``settings-likelihood.toml`` from
``fit``, and an ``eval`` that tried each brain 3 times as if it had failed.

The disk is filled for real, without mocks: each command runs under ``RLIMIT_FSIZE`` (with
SIGXFSZ ignored), so a write past that size fails with ``EFBIG`` (``File too large``), an
error of the same kind as ``ENOSPC``. Real processes: the commands, their engines and brains
over loopback Zenoh."""

from __future__ import annotations

import errno
import pickle
import resource
import shutil
import signal
import subprocess
import sys
from collections.abc import Callable
from pathlib import Path

import pytest

from bridge.recording.atomic import OutputError, disk_full, disk_full_in, write_text
from toyroom.evaluation.noroom import check_room

pytestmark = pytest.mark.process

TIMEOUT_S = 600


def _file_size_limit(size: int) -> Callable[[], None]:
    """For ``preexec_fn``: files of this process grow to ``size`` bytes at most (EFBIG past it)."""

    def limit() -> None:
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        resource.setrlimit(resource.RLIMIT_FSIZE, (size, size))

    return limit


def toyroom(*args: str, limit: int | None = None) -> subprocess.CompletedProcess[str]:
    """``python -m toyroom ARGS``, its files limited to ``limit`` bytes."""
    return subprocess.run(
        [sys.executable, "-m", "toyroom", *args],
        capture_output=True,
        text=True,
        timeout=TIMEOUT_S,
        preexec_fn=None if limit is None else _file_size_limit(limit),
    )


def _lines(result: subprocess.CompletedProcess[str]) -> list[str]:
    return [line for line in result.stderr.splitlines() if line.strip()]


def _partial(folder: Path) -> list[str]:
    """The temporary files a write left behind in ``folder`` (none should be)."""
    return sorted(p.name for p in folder.rglob(".*partial*"))


@pytest.fixture(scope="module")
def runs(tmp_path_factory: pytest.TempPathFactory) -> list[Path]:
    """Two finished runs' folders (sally-anne: a 1 MB trace and a 0.5 MB mind.csv; paper-1)."""
    folder = tmp_path_factory.mktemp("runs")
    made = []
    for scenario in ("sally-anne", "paper-1"):
        out = folder / scenario
        result = toyroom("run", "--scenario", scenario, "--no-live", "--out", str(out))
        assert result.returncode == 0, result.stderr[-2000:]
        made.append(out)
    return made


def test_infer_on_a_full_disk_is_one_line_and_writes_no_half_file(runs: list[Path], tmp_path: Path) -> None:
    out = tmp_path / "inferred"
    result = toyroom("infer", str(runs[0] / "trace.jsonl"), "--out", str(out), limit=100_000)
    expected = f"toyroom infer: file too large writing {out}/trace.jsonl"
    assert (result.returncode, _lines(result)) == (1, [expected]), (
        f"expected exit 1 and the one line {expected!r}, got exit {result.returncode} and:\n{result.stderr}"
    )
    assert sorted(p.name for p in out.iterdir()) == [], "a half-written output was left"


def test_the_brains_outputs_on_a_full_disk_are_one_line_and_none_half_written(
    runs: list[Path], tmp_path: Path
) -> None:
    """``toyroom infer`` into the run's own folder: the brain writes ``mind.csv`` (0.5 MB)."""
    folder = tmp_path / "run"
    shutil.copytree(runs[0], folder)
    for name in ("mind.csv", "report.md", "beliefs.png", "preferences.png"):
        (folder / name).unlink()
    result = toyroom("infer", str(folder / "trace.jsonl"), "--out", str(folder), limit=100_000)
    expected = f"brain: file too large writing {folder}/mind.csv"
    assert (result.returncode, _lines(result)) == (1, [expected]), (
        f"expected exit 1 and the one line {expected!r}, got exit {result.returncode} and:\n{result.stderr}"
    )
    assert not (folder / "mind.csv").exists() and _partial(folder) == [], "a half-written mind.csv was left"


def test_fit_on_a_full_disk_is_one_line_and_leaves_the_folder_as_it_was(
    runs: list[Path], tmp_path: Path
) -> None:
    out = tmp_path / "fit"
    out.mkdir()
    args = ["fit", *(str(r / "trace.jsonl") for r in runs), "--params", "beta", "--grid", "beta=1,2"]
    args += ["--models", "graded", "--folds", "2", "--workers", "1", "--no-progress", "--out", str(out)]
    result = toyroom(*args, limit=1000)  # settings.toml is about 1.3 kB
    expected = f"toyroom fit: file too large writing {out}/settings.toml"
    assert (result.returncode, _lines(result)) == (1, [expected]), (
        f"expected exit 1 and the one line {expected!r}, got exit {result.returncode} and:\n{result.stderr}"
    )
    assert sorted(p.name for p in out.iterdir()) == [], "fit left a file (half-written, or one of a set)"


def test_eval_on_a_full_disk_stops_at_once_keeping_what_finished(tmp_path: Path) -> None:
    """The brain cannot write its minds: the run is not tried again as if the brain had
    failed, and no episode is counted as failed; the evaluation stops, says so in one line
    of its own and keeps its state, and the same command with room finishes it."""
    out = tmp_path / "e"
    args = ["eval", "--episodes", "1", "--seed", "3", "--max-ticks", "100", "--policies", "none"]
    args += ["--workers", "1", "--batch", "1", "--out", str(out)]
    full = toyroom(*args, limit=50_000)
    said = [line for line in _lines(full) if line.startswith("toyroom eval:")]
    assert full.returncode == 1 and len(said) == 1, (
        f"expected exit 1 and one line, got {full.returncode}:\n{said}"
    )
    assert "found no room to write (" in said[0] and "File too large" in said[0], said[0]
    assert said[0].endswith(
        f"kept 0 of 1 episodes in {out}/episodes.jsonl: make room and run the same command again"
    ), said[0]
    assert "attempt 1 of 3" not in full.stderr, "a run that found no room was tried again"
    assert not list(out.rglob("*.failed1.log")), "a run that found no room was tried again"
    assert not (out / "metrics.json").exists(), "an evaluation that could not finish wrote metrics.json"
    assert (out / "unfinished-eval.json").is_file(), "its state (to resume it) was not kept"

    again = toyroom(*args)
    assert again.returncode == 0, again.stderr[-2000:]
    assert (out / "metrics.json").is_file()


def _write_limited(path: Path, text: str, limit: int) -> subprocess.CompletedProcess[str]:
    """``write_text(path, text)`` in a process whose files grow to ``limit`` bytes at most."""
    code = (
        "import sys; from pathlib import Path; from bridge.recording.atomic import write_text\n"
        "try:\n    write_text(Path(sys.argv[1]), sys.argv[2])\n"
        "except OSError as err:\n    print(err); sys.exit(1)\n"
    )
    return subprocess.run(
        [sys.executable, "-c", code, str(path), text],
        capture_output=True,
        text=True,
        timeout=60,
        preexec_fn=_file_size_limit(limit),
    )


def test_a_write_that_finds_no_room_leaves_the_earlier_file_whole(tmp_path: Path) -> None:
    path = tmp_path / "metrics.json"
    write_text(path, "earlier\n")
    result = _write_limited(path, "x" * 5000, 1000)
    assert result.returncode == 1, result
    assert result.stdout.strip() == f"file too large writing {path}", result.stdout
    assert path.read_text() == "earlier\n", "the earlier file was spoilt"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["metrics.json"], "a temporary file was left"


def test_a_full_disk_is_told_from_other_errors() -> None:
    for code in (errno.ENOSPC, errno.EDQUOT, errno.EFBIG):
        assert disk_full(OSError(code, "x")), code
    assert not disk_full(OSError(errno.EACCES, "x"))
    assert disk_full_in("ok\nOSError: [Errno 28] No space left on device\n") == (
        errno.ENOSPC,
        "OSError: [Errno 28] No space left on device",
    )
    assert disk_full_in("brain: engine 'x' lost\n") is None
    error = OutputError(OSError(errno.ENOSPC, "No space left on device"), Path("e/metrics.json"))
    again = pickle.loads(pickle.dumps(error))  # as a Ray task's error comes back
    assert (str(again), again.errno) == ("no space left on device writing e/metrics.json", errno.ENOSPC)


def test_a_node_that_found_no_room_is_not_tried_again(tmp_path: Path) -> None:
    log = tmp_path / "ep-btom-observe.brain.log"
    log.write_text("Traceback ...\nOSError: [Errno 122] Disk quota exceeded\n")
    with pytest.raises(OutputError, match="ep-btom-observe: the brain found no room to write"):
        check_room(RuntimeError("ep-btom-observe: the brain failed"), tmp_path, "ep-btom-observe")
    check_room(RuntimeError("ep-other: the brain failed"), tmp_path, "ep-other")  # its log says nothing
