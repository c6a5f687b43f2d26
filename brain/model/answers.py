"""A person's answer to the robot's question (protocol 1.6's ``ask`` and ``answer``) as
evidence about what they want: a likelihood over their favourite goal with a stated
reliability, not an overwrite (people may say one thing and do another). Pure."""

from __future__ import annotations

import numpy as np

from .arrays import FloatArray
from .desires import Desires


def answer_likelihood(n_goals: int, item: int | None, wants: bool, reliability: float) -> FloatArray:
    """``(D,)`` P(the answer | the person's favourite goal is ``d``), goals the ``D - 1`` items
    then ``out``. The answer is about item index ``item`` (``None``: no item, "nothing": it
    points at ``out``) and says whether they want it. A true answer has probability
    ``reliability``; the rest is spread evenly over the goals it would be false for."""
    goals = np.arange(n_goals)
    if item is None or wants:  # "I want <item>" (or "nothing": out)
        target = n_goals - 1 if item is None else item
        return np.where(goals == target, reliability, (1.0 - reliability) / max(n_goals - 1, 1))
    return np.where(goals == item, 1.0 - reliability, reliability)  # "not <item>"


def said_over(desires: Desires | None, said: FloatArray) -> FloatArray:
    """``said`` ``(D,)`` over a model's candidate desires: ``(U,)`` by each candidate's most
    wanted goal (ties split), or ``said`` itself for a model whose desires are the goals."""
    return said if desires is None else desires.wanted @ said


def open_answers(preference: FloatArray, reliability: float) -> tuple[FloatArray, FloatArray]:
    """What an open question ("what are you looking for?") may bring, over the favourite goal
    ``preference`` ``(D,)`` (the items, then ``out``): ``(odds, after)``, ``odds`` ``(D,)``
    P(the answer names goal ``a``; ``out``: "nothing") and ``after`` ``(D, D)`` the preference
    once answer ``a`` is heard (row ``a``; a row of an answer that cannot come is ``preference``
    itself). The answers' likelihood is :func:`answer_likelihood`'s."""
    n = len(preference)
    said = np.stack([answer_likelihood(n, None if a == n - 1 else a, True, reliability) for a in range(n)])
    joint = said * preference[None, :]
    odds = joint.sum(axis=1)
    after = np.divide(joint, odds[:, None], out=np.tile(preference, (n, 1)), where=odds[:, None] > 0)
    return odds, after
