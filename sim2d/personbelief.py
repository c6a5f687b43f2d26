"""A simulated person's own belief (what ``engine/truth`` reports as their true mind):
exact Bayesian over each item's location, with the map's visibility and the assumption that
unseen things stay put.

Perception is exact: an item in view is where it is seen (a carried item counts at its
carrier's location, as the brain reads it); an item not in view is not at any visible
location, so the probability there moves to the locations out of view, in proportion to
what they had. Speech replaces the belief about the item it names.

Rich minds (``Autonomy.forget``, ``Autonomy.miss``) add two imperfections: an item the person
failed to notice is left out of the percept (its belief stays as it was), and beliefs drift
toward uniform over the locations, which perception then corrects for what is in view.
They may also start knowing where things are, or sure of a place an item has left
(``Autonomy.knows``, ``Autonomy.stale``: :meth:`PersonBelief.start`).
"""

from __future__ import annotations

from collections.abc import Collection, Mapping, Sequence

import numpy as np
import numpy.typing as npt

FloatArray = npt.NDArray[np.float64]


class PersonBelief:
    """Beliefs over ``locations`` for each of ``items``: ``(K, L)`` rows that sum to one."""

    def __init__(self, items: Sequence[str], locations: Sequence[str]) -> None:
        self.items = list(items)
        self.locations = list(locations)
        self.p = np.full((len(items), len(locations)), 1.0 / max(len(locations), 1))

    def perceive(
        self, visible: Collection[str], seen: Mapping[str, str], missed: Collection[str] = ()
    ) -> None:
        """Update on a percept: ``visible`` location ids, and where each item in view is;
        the beliefs about items in ``missed`` (in view, not noticed) are left alone."""
        mask = np.array([loc in visible for loc in self.locations])
        for k, item in enumerate(self.items):
            if item in missed:
                continue
            if item in seen:
                self.p[k] = 0.0
                self.p[k, self.locations.index(seen[item])] = 1.0
                continue
            row = np.where(mask, 0.0, self.p[k])
            total = row.sum()
            if total > 0:
                self.p[k] = row / total
            elif (~mask).any():  # it was believed in view but is gone: anywhere out of view
                self.p[k] = np.where(mask, 0.0, 1.0) / (~mask).sum()

    def start(self, truth: Mapping[str, str], knows: float, stale: float, rng: np.random.Generator) -> None:
        """Draw what the person knows before the episode (``Autonomy.knows``,
        ``Autonomy.stale``): per item, sure of ``truth[item]`` with probability ``knows``, sure
        of another location (uniformly) with ``stale``, else uniform as before."""
        for item in self.items:
            draw, other = rng.random(), rng.random()
            where = truth.get(item)
            if where is None or draw >= knows + stale:
                continue
            others = [loc for loc in self.locations if loc != where]
            if draw < knows or not others:
                self.told(item, where)
            else:
                self.told(item, others[int(other * len(others))])

    def sureness(self, item: str) -> float:
        """The probability of the most probable location of ``item``."""
        return float(self.of(item).max())

    def forget(self, rate: float) -> None:
        """Every belief drifts toward uniform: ``p <- (1 - rate) p + rate / L`` (what is in
        view is put right by the next :meth:`perceive`)."""
        if rate > 0 and self.locations:
            self.p = (1.0 - rate) * self.p + rate / len(self.locations)

    def told(self, item: str, location: str) -> None:
        """Being told where ``item`` is replaces the belief about it."""
        k = self.items.index(item)
        self.p[k] = 0.0
        self.p[k, self.locations.index(location)] = 1.0

    def of(self, item: str) -> FloatArray:
        """``(L,)`` the belief about ``item``."""
        return self.p[self.items.index(item)]

    def most_likely(self, item: str, exclude: Collection[str] = ()) -> str | None:
        """The most probable location of ``item`` (ties: the first), skipping ``exclude``."""
        row = self.of(item).copy()
        for loc in exclude:
            row[self.locations.index(loc)] = -1.0
        best = int(np.argmax(row))
        return self.locations[best] if row[best] > 0 else None
