"""``toyroom view --screenshot`` saves a picture only of a world it can draw: with no engine,
an engine of another protocol version, or no brain, it saves nothing and exits 1 saying
which, instead of a blank PNG and exit 0."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import matplotlib.image
import msgspec
from support import EngineProcess, golden_examples

from bridge import Bridge, serve_info
from protocol import EngineInfo


def screenshot(world: str, shot: Path, after: float = 2.0) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [
            sys.executable,
            "-m",
            "toyroom",
            "view",
            "--world",
            world,
            "--screenshot",
            str(shot),
            "--after",
            str(after),
        ],
        capture_output=True,
        text=True,
        timeout=180,
    )


def assert_refused(result: subprocess.CompletedProcess[str], shot: Path, says: str) -> None:
    assert result.returncode == 1, f"exit {result.returncode}:\n{result.stdout}\n{result.stderr}"
    assert "toyroom view: no screenshot saved: " in result.stderr and says in result.stderr, result.stderr
    assert "Traceback" not in result.stderr, result.stderr
    assert not shot.exists(), "a picture was saved of a world that could not be drawn"


def test_no_engine_no_screenshot(world: str, tmp_path: Path) -> None:
    shot = tmp_path / "view.png"
    assert_refused(screenshot(world, shot, after=1.0), shot, f"no engine answered on world '{world}'")


def test_an_engine_of_another_major_version_no_screenshot(world: str, tmp_path: Path) -> None:
    info = golden_examples()["engine_info"]
    assert isinstance(info, EngineInfo)
    newer = msgspec.structs.replace(info, protocol="2.0", world=world)
    shot = tmp_path / "view.png"
    with Bridge(world) as engine:
        serve_info(engine, lambda: newer)
        result = screenshot(world, shot)
    assert_refused(result, shot, "cannot be drawn")
    assert "2.0" in result.stderr, result.stderr


def test_an_engine_without_a_brain_no_screenshot(world: str, tmp_path: Path) -> None:
    shot = tmp_path / "view.png"
    with EngineProcess(world, "--scenario", "paper-1", "--realtime", "1"):
        result = screenshot(world, shot)
    assert_refused(result, shot, f"no brain published a mind on world '{world}'")


def test_an_engine_and_a_brain_give_a_picture(living_world: str, tmp_path: Path) -> None:
    shot = tmp_path / "view.png"
    result = screenshot(living_world, shot)
    assert result.returncode == 0, result.stderr
    image = matplotlib.image.imread(str(shot))
    assert image.shape[0] > 100 and image[:, :, :3].std() > 0.02, "a blank picture"
