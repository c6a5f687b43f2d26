"""Solved Q-values kept in a folder, so that brain processes share them (``python -m brain
--values-cache DIR``; ``toyroom eval`` gives all of its runs one): a map's value iteration,
about a second on an evaluation house, then runs once per evaluation instead of once per run.

A file is named by a digest of the scene without its agents, the planning settings
(:data:`brain.model.planner.PLANNING`) and the source of the modules that define the MDP,
so a changed planner never reads old values. Files are written whole (to a temporary name,
then renamed), so a brain reading while another writes sees the file or nothing; a file
that cannot be read is solved again, with a warning.
"""

from __future__ import annotations

import hashlib
import logging
import os
import zipfile
from functools import cache
from pathlib import Path

import msgspec
import numpy as np

from protocol import Scene

from ..model import arrays, desires, goalvalues, planner, world
from ..model.arrays import FloatArray

log = logging.getLogger(__name__)


SOURCES = (planner, goalvalues, desires, world, arrays)
"""The modules whose source defines the MDP and its solution (:func:`brain.model.planner.solve`
solves every candidate desire with :func:`brain.model.goalvalues.solve_goals`): a change to
any of them names every stored file anew."""


@cache
def _sources() -> bytes:
    """A digest of the code that defines the MDP and its solution (:data:`SOURCES`)."""
    digest = hashlib.sha256()
    for module in SOURCES:
        digest.update(Path(module.__file__ or "").read_bytes())
    return digest.digest()


class ValueDirectory:
    """A folder of ``<digest>.npz`` files, each a scene's ``(U, D)`` desires and ``(U, S, A)``
    Q-values (:func:`brain.model.planner.solve`)."""

    def __init__(self, directory: Path) -> None:
        self.directory = directory
        directory.mkdir(parents=True, exist_ok=True)

    def path(self, scene: Scene, key: tuple[object, ...]) -> Path:
        """The file of ``scene`` (without its agents) under the settings ``key``."""
        digest = hashlib.sha256(_sources() + msgspec.json.encode(scene) + repr(key).encode())
        return self.directory / f"{digest.hexdigest()[:32]}.npz"

    def load(self, scene: Scene, key: tuple[object, ...]) -> tuple[FloatArray, FloatArray] | None:
        """The stored desires and Q-values, or ``None`` (never stored, or unreadable)."""
        path = self.path(scene, key)
        if not path.exists():
            return None
        try:
            with np.load(path) as stored:
                return stored["u"], stored["qs"]
        except (OSError, ValueError, KeyError, EOFError, zipfile.BadZipFile) as err:
            log.warning("cannot read the stored Q-values %s (%s): solving again", path, err)
            return None

    def save(self, scene: Scene, key: tuple[object, ...], u: FloatArray, qs: FloatArray) -> None:
        """Store them (a failure to write is a warning: the values are only a cache)."""
        path = self.path(scene, key)
        partial = path.with_name(f"{path.stem}.{os.getpid()}.part")
        try:
            with partial.open("wb") as out:
                np.savez(out, u=u, qs=qs)
            os.replace(partial, path)
        except OSError as err:
            log.warning("cannot store the Q-values in %s (%s)", path, err)
            partial.unlink(missing_ok=True)
