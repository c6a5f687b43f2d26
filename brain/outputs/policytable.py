"""The planner's Q-values of one scene as a file, so simulated people can act by the brain's
own planner (sim2d's ``planner = "model"`` minds) without importing the brain.

``python -m brain plan --scene SCENE.json --out FILE.npz [--set NAME=VALUE ...]`` writes it.
The ``.npz`` holds (``D`` goals: the items, then ``out``; ``C`` cells; ``H = K + 1`` held
codes, 0 for nothing, else item ``h - 1``; ``W`` worlds; ``A`` actions):

- ``q``: ``(D, C, H, W, A)`` float32 Q-values of the person whose favourite goal is ``d``
  (:func:`brain.model.desires.favourite_utilities`), ``-inf`` where the action is impossible;
- ``cells``: ``(C, 2)`` (col, row); ``worlds``: ``(W, K)`` item values ``2 l + held``
  (resting at location ``l``, or held by someone near ``l``); ``nearest``: ``(C,)`` the
  location a carried item counts at; ``moves``: ``(4, 2)`` the (d col, d row) of Up, Down,
  Left, Right;
- ``items``, ``locations``, ``goals``, ``actions``: the names along each axis;
- ``beta``, ``epsilon``, ``hazard``, ``decision_seconds``, ``wait_decisions``, ``table_version``:
  the settings people must act under for the brain's model of them to hold.

Actions follow :mod:`brain.model.planner`: Up, Down, Left, Right, Stay, Take(k), Drop, Play,
Use(k). A person acting by the table picks ``a`` with probability ``(1 - epsilon)
softmax(beta * Q_b)[a] + epsilon / A``, where ``Q_b`` is QMDP's expectation of ``q`` over
their belief (:func:`brain.model.graded.expected_q`).
"""

from __future__ import annotations

import dataclasses
from pathlib import Path
from typing import Any

import numpy as np

from protocol import Scene

from ..errors import BrainError
from ..model.planner import plan
from ..model.world import MOVE_STEPS, build_world_model
from ..settings import ModelSettings

TABLE_VERSION = 2
"""Bumped when the file's layout or the meaning of a value changes (2: ``wait_decisions`` is
when the first of a pause's Stays is read, one more each further decision time)."""


def action_names(items: tuple[str, ...]) -> list[str]:
    """The ``A`` action names in index order."""
    return [
        "up",
        "down",
        "left",
        "right",
        "stay",
        *(f"take:{k}" for k in items),
        "drop",
        "play",
        *(f"use:{k}" for k in items),
    ]


def policy_table(scene: Scene, settings: ModelSettings) -> dict[str, Any]:
    """The arrays of the file (see the module docstring).

    Raises:
        BrainError: when the scene has more worlds than ``settings.exact_max_worlds`` (the
            exact planner would not run on it)."""
    model = build_world_model(scene)
    if model.n_worlds > settings.exact_max_worlds:
        raise BrainError(
            f"scene '{scene.name}' has {model.n_worlds} worlds, more than exact_max_worlds = "
            f"{settings.exact_max_worlds}: people cannot act by the exact planner there"
        )
    policy = plan(model, dataclasses.replace(settings, desire_model="favourite"))
    D, C, H, W = len(policy.utilities), model.n_cells, model.n_items + 1, model.n_worlds
    q = policy.q.reshape(D, C, H, W, -1).astype(np.float32)
    return {
        "q": q,
        "cells": model.cells,
        "worlds": model.worlds,
        "nearest": model.nearest,
        "moves": np.array(MOVE_STEPS, dtype=np.int64),
        "items": np.array(model.items, dtype=str),
        "locations": np.array(model.locations, dtype=str),
        "goals": np.array([*model.items, "out"], dtype=str),
        "actions": np.array(action_names(model.items), dtype=str),
        "beta": np.float64(settings.beta),
        "epsilon": np.float64(settings.epsilon),
        "hazard": np.float64(settings.hazard),
        "decision_seconds": np.float64(settings.decision_seconds),
        "wait_decisions": np.float64(settings.wait_decisions),
        "table_version": np.int64(TABLE_VERSION),
    }


def write_policy_table(path: Path, scene: Scene, settings: ModelSettings) -> Path:
    """Write :func:`policy_table` to ``path`` (``.npz``, uncompressed) and return it."""
    path.parent.mkdir(parents=True, exist_ok=True)
    with path.open("wb") as handle:
        np.savez(handle, **policy_table(scene, settings))
    return path
