"""A person's current mode beside their lasting desire: errands and carries (pure numpy).

A person's latent state is ``(u, m)``: a lasting desire ``u`` (one of the ``U`` candidate
desires of :mod:`brain.model.desires`) and a current mode ``m``, one of ``M = 2 + K``:

- ``pursue``: they act on ``u`` (go for the item they want, or leave for good if ``u`` is
  ``out``);
- ``errand``: out and back. They act as someone who wants to leave (the candidate desire
  :func:`errand_candidate` picks), whatever ``u``; coming back resumes the pursuit of ``u``;
- ``carry:k`` (one per item ``k``): putting item ``k`` away, or carrying it to someone. Until
  they hold it they act as someone who wants ``k`` (to take it); holding it they take any
  action but Play alike (a carry's destination is not modelled: :func:`carry_likelihood`); the
  Drop of ``k`` ends the carry, and the pursuit of ``u`` resumes.

So a walk out is explained by the errand and a put-away by the carry, and ``u`` survives both
(Baker, Saxe and Tenenbaum 2009's "complex goals"; the persistent goal of SIPS / Plinf.jl).
The mode switches in continuous time at stated rates (:class:`ModeRates`, per second): a person
pursuing ``u`` starts an errand at ``errand_per_s`` and a carry at ``carry_per_s`` (of any
item, each alike); an errand or a carry ends on its own at ``resume_per_s``. Over a pause of
``t`` seconds the transition is the chain's exact ``expm(t Q)``. ``u`` keeps the hazard it had
(``ModelSettings.hazard``, per decision), except that time spent outside counts as one
decision: nobody is seen deciding anything there.

Shapes: the joint posterior is ``(G, U, M)`` (``G`` hypotheses of the person's initial
belief, ``U`` candidate desires, ``M`` modes); a decision's likelihood ``(G, U)`` under
pursuit, from which :func:`joint_likelihood` builds every mode's.
"""

from __future__ import annotations

import functools
from dataclasses import dataclass

import numpy as np
import scipy.linalg

from .arrays import FloatArray
from .inference import switched
from .planner import drop_action, n_actions, play_action

PURSUE, ERRAND, CARRY = 0, 1, 2
"""The mode axis: pursue, errand, then ``carry:k`` at ``CARRY + k``."""


MODE_NAMES = ("pursue", "errand", "carry")
"""The modes' names on the wire (``brain/mind``'s ``mode``; ``carry`` summed over the items,
which ``carry`` of the message gives one by one)."""


def on_the_wire(mode: FloatArray) -> tuple[FloatArray, FloatArray]:
    """``(3,)`` P(pursue, errand, carry any item) and ``(K,)`` P(carry each item) of an
    ``(M,)`` mode distribution."""
    return np.array([mode[PURSUE], mode[ERRAND], mode[CARRY:].sum()]), mode[CARRY:]


@dataclass(frozen=True)
class ModeRates:
    """The mode's switching rates, per second, for a scene of ``n_items`` items.

    Attributes:
        errand_per_s: rate at which a person pursuing their desire starts an errand (1/s).
        carry_per_s: rate at which they start carrying an item away (1/s, over all items).
        resume_per_s: rate at which an errand or a carry ends on its own (1/s):
            ``1 / resume_per_s`` is its mean length in seconds (a carry also ends at its Drop).
        n_items: ``K``.
    """

    errand_per_s: float
    carry_per_s: float
    resume_per_s: float
    n_items: int

    @property
    def generator(self) -> FloatArray:
        """``(M, M)`` the chain's rate matrix ``Q`` (rows sum to 0)."""
        M = CARRY + self.n_items
        q = np.zeros((M, M))
        q[PURSUE, ERRAND] = self.errand_per_s
        q[PURSUE, CARRY:] = self.carry_per_s / max(self.n_items, 1)
        q[ERRAND:, PURSUE] = self.resume_per_s
        q[np.arange(M), np.arange(M)] = -q.sum(axis=1)
        return q

    def transition(self, seconds: float) -> FloatArray:
        """``(M, M)`` ``T[m_prev, m] = P(m after seconds | m_prev)``: ``expm(seconds Q)``
        (the identity for 0)."""
        return _expm(self, round(max(seconds, 0.0), 6))

    @property
    def stationary(self) -> FloatArray:
        """``(M,)`` the chain's long-run share of each mode: the prior at first sight."""
        out = np.zeros(CARRY + self.n_items)
        out[PURSUE] = self.resume_per_s
        out[ERRAND] = self.errand_per_s
        out[CARRY:] = self.carry_per_s / max(self.n_items, 1)
        return out / out.sum()


@functools.lru_cache(maxsize=4096)
def _expm(rates: ModeRates, seconds: float) -> FloatArray:
    if seconds <= 0:
        return np.eye(CARRY + rates.n_items)
    out = scipy.linalg.expm(seconds * rates.generator)
    out = np.clip(out, 0.0, None)
    out.setflags(write=False)
    return out / out.sum(axis=1, keepdims=True)


def errand_candidate(utilities: FloatArray) -> int:
    """The candidate desire an errand plans as: the one that most prefers leaving over every
    item (``utilities`` ``(U, D)``, ``out`` last: the favourite ``out``, or the graded vector
    with ``out`` high and every item low)."""
    return item_candidate(utilities, utilities.shape[1] - 1)


def item_candidate(utilities: FloatArray, goal: int) -> int:
    """The candidate desire that most prefers goal ``goal`` over every other (a carry of item
    ``goal`` goes to take it as this one would)."""
    others = np.delete(utilities, goal, axis=1)
    return int(np.argmax(utilities[:, goal] - others.max(axis=1)))


def carry_likelihood(action: int, n_items: int, epsilon: float) -> float:
    """The likelihood of ``action`` for a person carrying an item away: every action but Play
    alike (where they take it is not modelled), Play at the floor ``epsilon / A``."""
    A = n_actions(n_items)
    if action == play_action(n_items):
        return epsilon / A
    return (1.0 - epsilon) / (A - 1) + epsilon / A


@dataclass(frozen=True)
class ModeColumns:
    """Where each mode's likelihood comes from: the candidate an errand plans as, and the one
    each carry goes to take its item as."""

    errand: int
    items: tuple[int, ...]
    epsilon: float

    @classmethod
    def of(cls, utilities: FloatArray, epsilon: float) -> ModeColumns:
        K = utilities.shape[1] - 1
        return cls(
            errand_candidate(utilities), tuple(item_candidate(utilities, k) for k in range(K)), epsilon
        )


def joint_likelihood(
    likelihood: FloatArray, decision: tuple[int, int, int], columns: ModeColumns
) -> FloatArray:
    """``(G, U, M)`` a decision's likelihood in each mode from its ``(G, U)`` likelihood under
    pursuit and the decision ``(cell, held, action)`` (``held``: 0 for nothing, else item + 1)."""
    G, U = likelihood.shape
    K = len(columns.items)
    out = np.empty((G, U, CARRY + K))
    out[:, :, PURSUE] = likelihood
    out[:, :, ERRAND] = likelihood[:, columns.errand : columns.errand + 1]
    held, action = decision[1], decision[2]
    for k, column in enumerate(columns.items):
        if held == k + 1:
            out[:, :, CARRY + k] = carry_likelihood(action, K, columns.epsilon)
        else:
            out[:, :, CARRY + k] = likelihood[:, column : column + 1]
    return out


def dropped_carry(decision: tuple[int, int, int] | None, n_items: int) -> int | None:
    """The carry the decision ends (its item), when it is the Drop of the item held."""
    if decision is None or decision[2] != drop_action(n_items) or decision[1] == 0:
        return None
    return decision[1] - 1


def joint_prior(desires: FloatArray, rates: ModeRates) -> FloatArray:
    """``(G, U, M)`` the joint at first sight from a ``(G, U)`` prior: the mode at its
    long-run shares, independent of the rest."""
    return desires[:, :, None] * rates.stationary[None, None, :]


def switch_joint(
    joint: FloatArray, switch: float, transition: FloatArray, base: FloatArray | None
) -> FloatArray:
    """``(G, U, M)`` after a pause: the desire redrawn with probability ``switch`` (from
    ``base`` ``(U,)``, else uniformly: :func:`brain.model.inference.switched`), then the mode's
    ``(M, M)`` transition."""
    if switch > 0:
        joint = np.moveaxis(switched(np.moveaxis(joint, 1, -1), switch, base), -1, 1)
    return joint @ transition


@dataclass(frozen=True)
class ModeStep:
    """What a step of the joint needs besides the joint: the pause's switches, the decision's
    likelihood in each mode and the decision."""

    likelihood: FloatArray | None
    """``(G, U, M)`` (:func:`joint_likelihood`, times what the person said over ``U``);
    ``None`` for a percept alone."""
    decision: tuple[int, int, int] | None
    switch: float
    transition: FloatArray


def mode_step(joint: FloatArray, step: ModeStep, base: FloatArray | None = None) -> tuple[FloatArray, float]:
    """``(G, U, M)`` joint after a step and the step's evidence: the pause's switches
    (:func:`switch_joint`), the step's likelihood in each mode, then a Drop of the item
    carried ends its carry (the pursuit resumes)."""
    joint = switch_joint(joint, step.switch, step.transition, base)
    if step.likelihood is not None:
        joint = joint * step.likelihood
    total = float(joint.sum())
    joint = joint / total
    ended = dropped_carry(step.decision, joint.shape[2] - CARRY)
    if ended is not None:
        joint = joint.copy()
        joint[:, :, PURSUE] += joint[:, :, CARRY + ended]
        joint[:, :, CARRY + ended] = 0.0
    return joint, total


def mode_back(back: FloatArray, step: ModeStep) -> FloatArray:
    """The backward message through a step, the adjoint of :func:`mode_step` (uniform redraw):
    the carry's end, the likelihood, the mode's transition transposed, the desire's switch."""
    ended = dropped_carry(step.decision, back.shape[2] - CARRY)
    if ended is not None:
        back = back.copy()
        back[:, :, CARRY + ended] = back[:, :, PURSUE]
    if step.likelihood is not None:
        back = back * step.likelihood
    back = back @ step.transition.T
    if step.switch > 0:  # H^T for a uniform redraw: (1 - s) back + s mean(back over U)
        back = (1.0 - step.switch) * back + step.switch * back.mean(axis=1, keepdims=True)
    return back / back.sum()
