"""The brain's planner table for episodes whose people act by it (``--minds model``).

Two processes, since bridge imports neither sim2d nor the brain: ``python -m sim2d scene``
prints the episode's scene, ``python -m brain plan`` solves it under the evaluation's settings
(its ``--settings`` and ``--set`` options) and writes the table the engine is started with
(``python -m sim2d --policy``). Tables are kept by a hash of the scene's map and items and of
the settings, so the episodes of one map share one.
"""

from __future__ import annotations

import hashlib
import json
import sys
from collections.abc import Sequence
from pathlib import Path

from .interrupt import NODES

SETTINGS_OPTIONS = ("--settings", "--set")


def settings_options(args: Sequence[str]) -> list[str]:
    """The ``--settings FILE`` and ``--set NAME=VALUE`` pairs of a brain's options."""
    out: list[str] = []
    for flag, value in zip(args, args[1:], strict=False):
        if flag in SETTINGS_OPTIONS:
            out += [flag, value]
    return out


def _run(command: list[str], what: str) -> str:
    result = NODES.run(command, timeout=300)
    if result.returncode != 0:
        raise RuntimeError(f"{what}: {result.stderr.strip() or result.stdout.strip()}")
    return result.stdout


def policy_table(scenario: Path, brain_args: Sequence[str], directory: Path) -> Path:
    """The table of ``scenario`` under the settings in ``brain_args``, in ``directory``
    (made on first use).

    Raises:
        RuntimeError: when the scene cannot be read or solved (the process's message)."""
    scene_text = _run(
        [sys.executable, "-m", "sim2d", "scene", "--scenario", str(scenario)], f"scene of {scenario}"
    )
    scene = json.loads(scene_text)
    scene.pop("agents", None)  # who lives there does not change the planner
    options = settings_options(brain_args)
    key = hashlib.sha256(json.dumps([scene, options], sort_keys=True).encode()).hexdigest()[:16]
    path = directory / f"policy-{key}.npz"
    if path.is_file():
        return path
    directory.mkdir(parents=True, exist_ok=True)
    scene_path = directory / f"scene-{key}.json"
    scene_path.write_text(scene_text, encoding="utf-8")
    partial = path.with_suffix(".partial.npz")
    _run(
        [sys.executable, "-m", "brain", "plan", "--scene", str(scene_path), "--out", str(partial), *options],
        f"planning {scenario}",
    )
    partial.replace(path)
    return path
