"""The brain's planner as a table of Q-values (``python -m brain plan`` writes it; the file's
layout is in ``brain.outputs.policytable``), and the choice it gives a person.

sim2d reads the file and never imports the brain: the two meet on the file, as on the wire.
A person's choice is the brain's model of it: QMDP's expected Q-values over their belief
(an action impossible in a world counts what Stay does there; impossible in every believed
world, it is never chosen), then ``(1 - epsilon) softmax(beta * Q) + epsilon / A``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import numpy.typing as npt

from ..errors import Sim2dError

FloatArray = npt.NDArray[np.float64]
IntArray = npt.NDArray[np.int64]

TABLE_VERSION = 2
STAY = 4
KEYS = ("q", "cells", "worlds", "nearest", "moves", "items", "locations", "goals", "actions")
SCALARS = ("beta", "epsilon", "hazard", "decision_seconds", "wait_decisions", "table_version")


class PolicyTableError(Sim2dError):
    """A policy table that cannot be read or does not fit the scenario."""

    def __init__(self, path: Path, message: str) -> None:
        super().__init__(f"policy table {path}: {message}")
        self.path = path


@dataclass(frozen=True)
class PolicyTable:
    """The planner's output for one scene.

    Attributes:
        q: ``(D, C, H, W, A)`` Q-values (goal, cell, held code, world, action).
        cell_index: (col, row) -> index along ``C``.
        worlds: ``(W, K)`` item values ``2 l + held``.
        nearest: ``(C,)`` the location index a carried item counts at.
        moves: ``(4, 2)`` (d col, d row) of the four move actions.
        items, locations, goals, actions: the names along ``K``, ``L``, ``D``, ``A``.
        beta, epsilon, hazard: the choice rule and the preference switch per decision.
        decision_seconds, wait_decisions: a decision's time, and the brain's reading of waits
            (:mod:`sim2d.people.planned`: how long a Stay stands).
    """

    path: Path
    q: npt.NDArray[np.float32]
    cell_index: dict[tuple[int, int], int]
    worlds: IntArray
    nearest: IntArray
    moves: IntArray
    items: tuple[str, ...]
    locations: tuple[str, ...]
    goals: tuple[str, ...]
    actions: tuple[str, ...]
    beta: float
    epsilon: float
    hazard: float
    decision_seconds: float
    wait_decisions: float

    def check(self, items: Sequence[str], locations: Sequence[str], cells: Sequence[tuple[int, int]]) -> None:
        """Raise :class:`PolicyTableError` unless the table was made for a scene with these
        items, locations and walkable cells."""
        for name, mine, theirs in (
            ("items", self.items, tuple(items)),
            ("locations", self.locations, tuple(locations)),
            ("walkable cells", tuple(sorted(self.cell_index)), tuple(sorted(cells))),
        ):
            if mine != theirs:
                raise PolicyTableError(
                    self.path, f"made for another scene: its {name} are {_brief(mine)}, not {_brief(theirs)}"
                )

    def world_belief(self, values: FloatArray) -> FloatArray:
        """``(W,)`` the belief over worlds of independent ``(K, V)`` beliefs over each item's value."""
        K = self.worlds.shape[1]
        out = np.ones(len(self.worlds))
        for k in range(K):
            out *= values[k, self.worlds[:, k]]
        return out

    def choice(self, goal: int, cell: int, held: int, belief: FloatArray) -> FloatArray:
        """``(A,)`` the probability of each action for a person of favourite ``goal`` at
        ``cell`` holding ``held`` with the ``(W,)`` ``belief``."""
        q = self.q[goal, cell, held].astype(np.float64)  # (W, A)
        feasible = np.isfinite(q)
        stay = q[:, STAY]
        values = np.where(feasible, q, np.where(np.isfinite(stay), stay, 0.0)[:, None])
        expected = belief @ values
        possible = belief @ feasible.astype(np.float64) > 1e-12
        scaled = np.where(possible, self.beta * expected, -np.inf)
        weights = np.exp(scaled - scaled[possible].max())
        soft = weights / weights.sum()
        return (1.0 - self.epsilon) * soft + self.epsilon / len(soft)


def _brief(names: Sequence[object]) -> str:
    shown = ", ".join(str(n) for n in names[:6])
    return f"[{shown}{', ...' if len(names) > 6 else ''}] ({len(names)})"


def load_policy_table(path: Path) -> PolicyTable:
    """Read a table written by ``python -m brain plan``.

    Raises:
        PolicyTableError: naming what is missing or wrong."""
    try:
        with np.load(path, allow_pickle=False) as data:
            arrays = {key: data[key] for key in data.files}
    except (OSError, ValueError) as err:
        raise PolicyTableError(path, f"cannot be read ({err})") from err
    missing = [key for key in (*KEYS, *SCALARS) if key not in arrays]
    if missing:
        raise PolicyTableError(path, f"missing {', '.join(missing)} (not written by `python -m brain plan`?)")
    if int(arrays["table_version"]) != TABLE_VERSION:
        raise PolicyTableError(
            path, f"table_version {int(arrays['table_version'])}, this sim2d reads {TABLE_VERSION}"
        )
    q, cells = arrays["q"], arrays["cells"]
    names = (arrays["goals"], cells, arrays["items"], arrays["worlds"], arrays["actions"])
    shape = tuple(len(a) + (i == 2) for i, a in enumerate(names))
    if q.shape != shape:
        raise PolicyTableError(path, f"q has shape {q.shape}, its names say {shape}")
    return PolicyTable(
        path=path,
        q=q,
        cell_index={(int(c), int(r)): i for i, (c, r) in enumerate(cells)},
        worlds=arrays["worlds"].astype(np.int64),
        nearest=arrays["nearest"].astype(np.int64),
        moves=arrays["moves"].astype(np.int64),
        items=tuple(str(s) for s in arrays["items"]),
        locations=tuple(str(s) for s in arrays["locations"]),
        goals=tuple(str(s) for s in arrays["goals"]),
        actions=tuple(str(s) for s in arrays["actions"]),
        **{key: float(arrays[key]) for key in SCALARS[:-1]},
    )
