"""A simulated person's own belief (what ``engine/truth`` reports as their true mind):
exact Bayesian over each item's location, with the map's visibility and the assumption that
unseen things stay put.

Perception is exact: an item in view is where it is seen (a carried item counts at its
carrier's location, as the brain reads it); an item not in view is not at any visible
location, so the probability there moves to the locations out of view, in proportion to
what they had. An item the person saw carried, whose carrier then moved out of sight with
it, may be anywhere out of view (evenly): it went with its carrier. Speech replaces the
belief about the item it names.

Rich minds (``Autonomy.forget_per_tick``, ``Autonomy.miss``) add two imperfections: an item the person
failed to notice is left out of the percept (its belief stays as it was), and beliefs drift
toward uniform over the locations, which perception then corrects for what is in view.
They may also start knowing where things are, or sure of a place an item has left
(``Autonomy.knows``, ``Autonomy.stale``: :meth:`PersonBelief.start`).
"""

from __future__ import annotations

from collections.abc import Collection, Mapping, Sequence

import numpy as np
import numpy.typing as npt

from protocol import ItemBelief, Prob

FloatArray = npt.NDArray[np.float64]


class PersonBelief:
    """Beliefs over ``locations`` for each of ``items``: ``(K, L)`` rows that sum to one."""

    def __init__(self, items: Sequence[str], locations: Sequence[str]) -> None:
        self.items = list(items)
        self.locations = list(locations)
        self.p = np.full((len(items), len(locations)), 1.0 / max(len(locations), 1))
        self._row = {item: k for k, item in enumerate(self.items)}
        self._column = {loc: j for j, loc in enumerate(self.locations)}
        self._masks: dict[tuple[str, ...], tuple[npt.NDArray[np.bool_], FloatArray | None]] = {}
        self._last: tuple[object, bytes, FloatArray] | None = None
        """The last percept, the belief it met (as bytes) and the belief it made."""

    def _view(self, visible: Collection[str]) -> tuple[npt.NDArray[np.bool_], FloatArray | None]:
        """``(L,)`` which locations are in view, and the uniform belief over those out of view
        (``None`` when every location is in view); kept per set of visible locations."""
        key = tuple(visible)
        cached = self._masks.get(key)
        if cached is None:
            mask = np.array([loc in visible for loc in self.locations], dtype=bool)
            hidden = ~mask
            elsewhere = np.where(mask, 0.0, 1.0) / hidden.sum() if hidden.any() else None
            cached = self._masks[key] = (mask, elsewhere)
        return cached

    def perceive(
        self,
        visible: Collection[str],
        seen: Mapping[str, str],
        missed: Collection[str] = (),
        carried_off: Collection[str] = (),
    ) -> None:
        """Update on a percept: ``visible`` location ids, and where each item in view is;
        the beliefs about items in ``missed`` (in view, not noticed) are left alone; an item
        of ``carried_off`` (seen carried by someone who has since moved out of sight with it)
        may be anywhere out of view, evenly: it went with its carrier, it does not rest where
        the person saw it pass. The same percept meeting the same belief again (someone
        standing still) gives the same result without the arithmetic."""
        key = (tuple(visible), tuple(seen.items()), frozenset(missed), frozenset(carried_off))
        before = self.p
        met = before.tobytes()
        if self._last is not None and self._last[0] == key and self._last[1] == met:
            self.p = self._last[2].copy()
            return
        mask, elsewhere = self._view(visible)
        kept = np.where(mask, 0.0, before)
        totals = kept.sum(axis=1)
        after = np.divide(kept, totals[:, None], out=before.copy(), where=totals[:, None] > 0)
        if elsewhere is not None:  # believed in view but gone: anywhere out of view
            after[totals <= 0] = elsewhere
            for item in carried_off:  # went with its carrier: anywhere out of view
                after[self._row[item]] = elsewhere
        for item, where in seen.items():
            k = self._row[item]
            after[k] = 0.0
            after[k, self._column[where]] = 1.0
        for item in missed:
            after[self._row[item]] = before[self._row[item]]
        self.p = after
        self._last = (key, met, after.copy())

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


def item_beliefs(belief: PersonBelief) -> tuple[ItemBelief, ...]:
    """A belief as the protocol's ``ItemBelief`` list (probabilities to 6 places)."""
    return tuple(
        ItemBelief(
            item=item,
            locations=tuple(
                Prob(loc, round(float(p), 6))
                for loc, p in zip(belief.locations, belief.of(item), strict=True)
            ),
        )
        for item in belief.items
    )
