"""One person's rows of the factored unseen world: the few sets of the unseen items' origins
that their percepts have told apart.

A person's filter depends on where the unseen items rest only through what the person
perceived of them. Each row holds, per item, a set of origins ``sets`` ``(R, K, L)`` (bool):
every world whose items' origins lie in the row's sets gives the person the same percepts
so far, so one filter (one chain of the tracker) serves them all. A row starts with every
origin; when the person's cell sees spots of an item's set that the robot gives mass
(:meth:`PersonRows.split`), the row splits into one row per such spot and one for the rest
(the item not in view). Rows are kept to ``cap``, the heaviest first (:data:`MAX_ROWS` at
most: the mass of those dropped is lost, the factoring's one approximation of a person's
filter besides the truth read in a row for its unseen items, :meth:`PersonRows.origins`).

A row's prior is ``prod_k Q_k(A_k)`` under the robot's per-item belief ``Q`` ``(K, L)``; its
weight, that times the likelihood of the person's decisions under the row's filter. The
person's evidence about each item, ``lambda[k, l] = P(decisions | item k's origin is l)``
``(K, L)`` (:meth:`PersonRows.message`), is what the robot's belief multiplies in
(:mod:`brain.tracking.itemworld`). Pure numpy; no I/O.
"""

from __future__ import annotations

import numpy as np

from ..model.arrays import BoolArray, FloatArray, IntArray

ROWS_IN_ALL = 32
"""The most rows all the people of a scene keep together (each ``ROWS_IN_ALL // people``,
at most :data:`MAX_ROWS`: 16 each for two people, 4 each for eight; fewer where memory is
short, :func:`brain.model.size.factored_rows`): a tick's time grows with them, each row
costing about one person's filter (``docs/performance.md``)."""
MAX_ROWS = 16
"""The most rows one person keeps."""


def row_mass(sets: BoolArray, q: FloatArray) -> FloatArray:
    """``(R, K)`` each row's mass of each item under ``q`` ``(K, L)``: ``Q_k(A_k)``."""
    return np.einsum("rkl,kl->rk", sets, q)


def log_prior(sets: BoolArray, q: FloatArray) -> FloatArray:
    """``(R,)`` each row's log prior ``sum_k log Q_k(A_k)`` (``-inf``: ruled out)."""
    with np.errstate(divide="ignore"):
        return np.log(row_mass(sets, q)).sum(axis=1)


class PersonRows:
    """One person's rows (see the module's note).

    Args:
        support: ``(K, L)`` the origins the robot allows each item.
        cap: the most rows kept.
    """

    def __init__(self, support: BoolArray, cap: int = MAX_ROWS) -> None:
        self.sets: BoolArray = support[None].copy()
        self.cap = max(1, cap)

    def __len__(self) -> int:
        return len(self.sets)

    def restrict(self, q: FloatArray) -> IntArray:
        """Drop the rows ``q`` (the robot's belief now) rules out; returns the indices kept.
        When none is left (the robot saw what no row allowed, a row having been dropped for
        its weight), the first row is kept with the items it ruled out opened to every origin
        ``q`` allows (its filter heard other percepts of them: an approximation)."""
        alive = np.isfinite(log_prior(self.sets, q))
        if alive.any():
            kept = np.flatnonzero(alive)
            self.sets = self.sets[kept]
            return kept
        dead = row_mass(self.sets[:1], q)[0] <= 0  # (K,)
        self.sets = self.sets[:1].copy()
        self.sets[0, dead] = q[dead] > 0
        return np.zeros(1, dtype=np.int64)

    def split(self, seen: BoolArray, q: FloatArray, unknown: BoolArray, evidence: FloatArray) -> IntArray:
        """Split the rows on what a person's cell sees, ``seen`` ``(L,)``: for each item whose
        place is ``unknown`` ``(K,)`` and each row whose set holds spots in view with mass
        under ``q``, one row per such spot and one for the rest; after each item the rows are
        cut to ``cap`` by weight (``evidence`` ``(R,)``: each row's log-likelihood of the
        person's decisions). Returns, for each row now, the index of the row it came from."""
        source = np.arange(len(self.sets))
        positive = q > 0
        for k in np.flatnonzero(unknown):
            in_view = self.sets[:, k] & (seen & positive[k])[None, :]  # (R, L)
            rest = self.sets[:, k] & ~seen[None, :] & positive[k][None, :]
            needs = in_view.any(axis=1) & ((in_view.sum(axis=1) > 1) | rest.any(axis=1))
            if not needs.any():
                continue
            rows, spots = np.nonzero(in_view & needs[:, None])
            new_sets = [self.sets[~needs]]
            new_source = [source[~needs]]
            singles = self.sets[rows].copy()
            singles[:, k] = False
            singles[np.arange(len(rows)), k, spots] = True
            new_sets.append(singles)
            new_source.append(source[rows])
            keep_rest = needs & rest.any(axis=1)
            remainder = self.sets[keep_rest].copy()
            remainder[:, k] = rest[keep_rest]
            new_sets.append(remainder)
            new_source.append(source[keep_rest])
            self.sets, source = np.concatenate(new_sets), np.concatenate(new_source)
            score = log_prior(self.sets, q) + evidence[source]
            order = np.argsort(-score, kind="stable")[: self.cap]
            order.sort()  # the rows kept in the order they were made
            self.sets, source = self.sets[order], source[order]
        return source

    def weights(self, q: FloatArray, evidence: FloatArray) -> FloatArray:
        """``(R,)`` each row's posterior: its prior under ``q`` ``(K, L)`` (the robot's belief,
        with the other people's evidence) times the likelihood of the person's decisions
        (``evidence`` ``(R,)``, log)."""
        log_w = log_prior(self.sets, q) + evidence
        if not np.isfinite(log_w.max()):  # the others' evidence left no row mass: the person's alone
            log_w = log_prior(self.sets, np.ones_like(q)) + evidence
        w = np.exp(log_w - log_w.max())
        return w / w.sum()

    def message(self, q: FloatArray, evidence: FloatArray) -> FloatArray:
        """``(K, L)`` the person's evidence about each item's origin, up to a factor per item:
        ``P(decisions | k at l) = sum_r P(decisions | r) P(r | k at l)`` with
        ``P(r | k at l) = [l in A_k] prior_r / Q_k(A_k)``, over the rows kept (renormalised: a
        row dropped for its weight is taken to have their average likelihood; an origin no
        row holds gets the rows' average, no evidence either way). Each item's row is scaled
        to a largest value of one."""
        mass = row_mass(self.sets, q)  # (R, K)
        with np.errstate(divide="ignore"):
            prior = np.log(mass).sum(axis=1)
        prior = np.exp(prior - prior.max())  # (R,)
        likelihood = np.exp(evidence - evidence.max())  # (R,)
        given = np.divide(prior[:, None], mass, out=np.zeros_like(mass), where=mass > 0)  # (R, K)
        num = np.einsum("rk,rkl->kl", given * likelihood[:, None], self.sets)
        den = np.einsum("rk,rkl->kl", given, self.sets)
        average = float(prior @ likelihood / prior.sum())
        lam = np.where(den > 0, num / np.where(den > 0, den, 1.0), average)
        top = lam.max(axis=1, keepdims=True)
        return np.divide(lam, top, out=np.ones_like(lam), where=top > 0)
