"""Shadow observers: other person models fed the same ticks as the live brain, each writing
its online ``mind`` messages to a JSON-lines file.

An observing brain does not change the world, so one run can stand for a run of every
observer: ``toyroom eval`` scores ``truebelief`` and ``perceptonly`` from these files and
``btom`` from the wire, which saves two engine runs per episode. The messages are exactly
what a live brain with that observer would publish (same code, same ticks).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import IO

from protocol import Event, Scene, State, encode

from ..model.revisions import SharedRevisions
from ..settings import ModelSettings
from ..tracking.tracker import MindTracker, Observer
from .results import MindCache, mind_message


def shadow_path(directory: Path, observer: Observer) -> Path:
    """Where the shadow ``observer``'s minds go: ``DIR/minds-<observer>.jsonl``."""
    return directory / f"minds-{observer.value}.jsonl"


class ShadowMinds:
    """Trackers of ``observers`` over ``scene``, writing into ``directory``.

    Args:
        scene: the engine's scene.
        observers: the person models to run alongside the live one.
        directory: created if missing; one file per observer (:func:`shadow_path`).
        settings: model parameters (the live brain's).
        revisions: belief revisions shared with the live tracker (``perceptonly`` revises
            as ``btom`` does: :mod:`brain.model.revisions`).
    """

    def __init__(
        self,
        scene: Scene,
        observers: Sequence[Observer],
        directory: Path,
        settings: ModelSettings,
        revisions: SharedRevisions | None = None,
    ) -> None:
        directory.mkdir(parents=True, exist_ok=True)
        self.scene = scene
        self.trackers = [MindTracker(scene, settings, observer, revisions) for observer in observers]
        self.files: list[IO[bytes]] = [shadow_path(directory, o).open("wb") for o in observers]
        self.minds: list[MindCache] = [{} for _ in observers]

    def observe(self, state: State, events: Sequence[Event]) -> None:
        """Feed one tick to every shadow tracker and write its ``mind`` line."""
        for tracker, file, minds in zip(self.trackers, self.files, self.minds, strict=True):
            tracker.observe(state, events)
            file.write(encode(mind_message(tracker, state, cache=minds)) + b"\n")

    def close(self) -> None:
        for file in self.files:
            file.close()
