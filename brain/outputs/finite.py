"""Non-finite numbers stop the brain: an estimate holding NaN or an infinity (a setting that
overflowed, a model fault) raises :class:`~brain.errors.NonFiniteError` naming the person,
the quantity and the tick, rather than going out in a ``mind`` message (which every
subscriber would drop as invalid) or into ``mind.csv``."""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

from ..errors import NonFiniteError
from ..model.estimates import Estimate
from ..model.world import WorldModel


def _first_bad(values: object) -> int | None:
    """Flat index of the first value that is NaN or infinite, ``None`` when all are finite."""
    array = np.asarray(values, dtype=np.float64).ravel()
    bad = np.flatnonzero(~np.isfinite(array))
    return int(bad[0]) if bad.size else None


def check_estimate(model: WorldModel, person: str, tick: int, est: Estimate) -> None:
    """``est``'s probabilities and utilities, each finite.

    Raises:
        NonFiniteError: naming ``person``, ``tick``, the quantity and the first bad value.
    """
    goals = (*model.items, "out")
    fields: list[tuple[str, object, Iterable[str]]] = [
        ("item beliefs", est.beliefs, (f"{i} at {loc}" for i in model.items for loc in model.locations)),
        ("preference", est.preference, goals),
        ("intention", [est.intention[2]], ("p",)),
        ("false-belief probability", est.false_belief, model.items),
    ]
    if est.desire is not None:
        fields.append(("desire utility", est.desire.utility, goals))
    if est.worlds is not None:
        fields.append(("belief over worlds", est.worlds, ()))
    for field, values, names in fields:
        index = _first_bad(values)
        if index is not None:
            value = np.asarray(values, dtype=np.float64).ravel()[index]
            label = next(iter(list(names)[index : index + 1]), f"entry {index}")
            raise NonFiniteError(person, tick, field, f"{value} for {label}")


def check_rows(rows: Iterable[tuple[int, str, str, str, float, float]]) -> None:
    """``mind.csv``'s rows ``(tick, person, quantity, item, p_online, p_smoothed)``: no NaN,
    and no infinity but a log-evidence of minus infinity (a decision the model gave no chance).

    Raises:
        NonFiniteError: naming the first bad row's person, tick and quantity.
    """
    for tick, person, quantity, item, online, smoothed in rows:
        for which, value in (("online", online), ("smoothed", smoothed)):
            if np.isnan(value) or (np.isinf(value) and not (quantity == "log_evidence" and value < 0)):
                raise NonFiniteError(person, tick, f"{quantity} ({which})", f"{value} for {item or '-'}")
