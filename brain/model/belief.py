"""Percepts and the paper's belief update.

A person at cell ``x`` perceives, for each item, the value it shows if it is in view (at a
location visible from ``x``, carried by someone they see, or carried by the person), or that
it is not in view; speech from the robot is a percept of the item it names. The believed
world moves as

    P(b_t = i | b_{t-1} = j, o_t)  ∝  P(o_t | x_t, w^i) · f(i, j),

normalised over ``i`` for each ``j`` (the percept comes from the true world, so it is no
evidence about the old belief), with ``f = r`` for ``i != j`` inside ``PW(j)``, 1 for
``i = j`` and 0 outside ``PW(j)``: the worlds that differ from ``j`` only in items the person
can now see (seen, or believed to be at a visible location). People assume unseen things
stay put, which is what makes false beliefs; but an item they believe held by someone out of
sight goes with its carrier: when the carrier goes out of sight with it, it may be held
anywhere out of sight (still held: a person who saw the robot carry the ball off believes the
robot has it, not that it rests where they saw it pass); :func:`changes` says which values
may change, and to what. ``P(o | x, w)`` is ``1 - delta`` per item whose percept ``w``
reproduces and ``delta`` per item it does not.
"""

from __future__ import annotations

from collections.abc import Collection, Sequence
from dataclasses import dataclass
from functools import cached_property

import numpy as np
import numpy.typing as npt

from .arrays import FloatArray
from .world import ABSENT, WorldModel, is_held, location_of, value_of

NOT_IN_VIEW = -1
UNNOTICED = -2
"""An item in view the person overlooks (:mod:`brain.model.person.lapses`): the percept says nothing
about it, and the person's belief about it stays as it was."""


@dataclass(frozen=True)
class Percept:
    """What a person perceives at cell index ``cell``: per item, the value it shows
    (:func:`~brain.model.world.value_of`), ``NOT_IN_VIEW`` or ``UNNOTICED``; ``lost``: the
    items they saw carried by someone else at their last percept and see no more (the carrier
    went out of sight with it: :func:`carried_off`)."""

    cell: int
    seen: tuple[int, ...]
    lost: tuple[int, ...] = ()


def true_values(
    model: WorldModel, resting: dict[str, str | None], holders: dict[str, int | None]
) -> tuple[int, ...]:
    """Every item's value in the true world: ``2 l`` resting at location ``l``, ``2 l + 1``
    held by someone near ``l`` (the location a carried item counts as being at).

    Args:
        model: the world model whose items and locations the values index.
        resting: item id -> location id where it rests (``None`` when carried; an item
            missing, or neither resting nor carried, is :data:`ABSENT` when the scene has one).
        holders: item id -> cell index of its carrier (``None`` when resting).
    """
    values = []
    for item in model.items:
        holder_cell = holders.get(item)
        if holder_cell is not None:
            values.append(value_of(int(model.nearest[holder_cell]), held=True))
        elif resting.get(item) is None and ABSENT in model.locations:
            values.append(value_of(model.locations.index(ABSENT)))
        else:
            values.append(value_of(model.locations.index(resting.get(item) or "")))
    return tuple(values)


PERCEPTS_KEPT = 50_000
"""The most percepts a world model keeps worked out (:attr:`WorldModel.percepts`; then it
starts again): a few episodes' worth."""


def percept(
    model: WorldModel, cell: int, truth: tuple[int, ...], own: int | None, carriers: Sequence[int] = ()
) -> Percept:
    """The percept at ``cell`` of a person holding item index ``own`` (or nothing).

    ``carriers``: per item, the cell index of whoever carries it (-1: nobody). A carried item
    is seen only where its carrier is seen (:meth:`WorldModel.sees_carrier`), not wherever
    the location it counts at is in view: an item carried through a hall counts at a
    location elsewhere, which shows nothing. Without ``carriers`` (or with -1 for a carried
    item) the carry location's sight is used. Worked out once per model and arguments (a
    percept is immutable: the kept one is handed out again)."""
    key = (int(cell), tuple(truth), own, tuple(int(c) for c in carriers))
    kept = model.percepts.get(key)
    if isinstance(kept, Percept):
        return kept
    if len(model.percepts) >= PERCEPTS_KEPT:
        model.percepts.clear()
    made = _percept(model, cell, truth, own, carriers)
    model.percepts[key] = made
    return made


def _percept(
    model: WorldModel, cell: int, truth: tuple[int, ...], own: int | None, carriers: Sequence[int]
) -> Percept:
    """:func:`percept`, worked out."""
    seen = []
    for k, value in enumerate(truth):
        carrier = carriers[k] if k < len(carriers) else -1
        if own == k:
            seen.append(value_of(int(model.nearest[cell]), held=True))
        elif is_held(value) and carrier >= 0:
            seen.append(value if bool(model.sees_carrier(cell, np.array(carrier))) else NOT_IN_VIEW)
        elif model.sees[cell, location_of(value)]:
            seen.append(value)
        else:
            seen.append(NOT_IN_VIEW)
    return Percept(cell=cell, seen=tuple(seen))


@dataclass(frozen=True)
class Changes:
    """Which believed item values may change on a percept, by the old value ``j``.

    Attributes:
        anywhere: ``(K, V)`` to any value, with the paper's weight ``r``: the item is in view,
            or ``j`` puts it at a place in view.
        carried: ``(K, V)`` redrawn among the held values out of view, evenly, before that:
            ``j`` has it held by someone the person just lost sight of (a carried item goes
            with its carrier, who keeps it as far as the person knows, wherever out of sight
            they went).
        hidden: ``(V,)`` the values whose place is out of view.
    """

    anywhere: npt.NDArray[np.bool_]
    carried: npt.NDArray[np.bool_]
    hidden: npt.NDArray[np.bool_]

    def allowed(self) -> npt.NDArray[np.bool_]:
        """``(K, V_i, V_j)`` whether the belief of item ``k`` may go from ``j`` to ``i`` by the
        paper's change (``i = j`` included)."""
        V = self.anywhere.shape[1]
        return np.eye(V, dtype=bool)[None] | self.anywhere[:, None, :]

    @property
    def lost(self) -> bool:
        """Whether any item is redrawn (:meth:`redraw` is not the identity)."""
        return bool(self.carried.any())

    def redraw(self) -> FloatArray:
        """``(K, V_i, V_j)`` the carried items' redraw: from a held value ``j`` the person lost
        sight of, every held value out of view alike (``j`` itself when none is); the identity
        elsewhere (columns sum to one)."""
        K, V = self.carried.shape
        to = is_held(np.arange(V)) & self.hidden
        if not to.any():
            return np.broadcast_to(np.eye(V), (K, V, V)).copy()
        spread = np.repeat((to / to.sum())[:, None], V, axis=1)  # (V_i, V_j)
        return np.where(self.carried[:, None, :], spread[None], np.eye(V)[None])


def redrawn(tensor: FloatArray, ch: Changes, first_axis: int = 1) -> FloatArray:
    """``tensor`` ``(N, V, ..., V)`` (one ``V`` axis per item from ``first_axis``) with each
    carried item's axis taken through :meth:`Changes.redraw` (a new array; ``tensor`` when
    nothing is redrawn)."""
    if not ch.lost:
        return tensor
    u = ch.redraw()
    for k in np.nonzero(ch.carried.any(axis=1))[0]:
        axis = first_axis + int(k)
        tensor = np.moveaxis(np.tensordot(tensor, u[k], axes=([axis], [1])), -1, axis)
    return tensor


def changes(model: WorldModel, p: Percept) -> Changes:
    """Which believed values may change on percept ``p`` (:class:`Changes`): an item the
    person overlooks changes not at all; one they just lost sight of in someone's hands
    (``p.lost``) may be held anywhere out of view."""
    values = np.arange(model.n_values)
    seen = np.array(p.seen)[:, None]  # (K, 1)
    visible = model.sees[p.cell][location_of(values)][None, :]  # (1, V)
    anywhere = (seen >= 0) | (visible & (seen != UNNOTICED))
    lost = np.isin(np.arange(model.n_items), p.lost)[:, None]  # (K, 1)
    carried = lost & (seen == NOT_IN_VIEW) & is_held(values)[None, :]
    return Changes(anywhere, carried, ~visible[0])


def carried_off(before: Percept | None, now: Percept, own: int | None, moved: Collection[int]) -> Percept:
    """``now``, with ``lost`` the items ``before`` (the person's last percept) saw held by
    someone else (not the person, who holds item index ``own`` or nothing), that ``now`` does
    not see and whose carrier moved (``moved``: item indices): carried off out of sight. A
    person who walks away from someone playing with an item loses nothing: it is where they
    left it."""
    if before is None:
        return now
    lost = tuple(
        k
        for k, (was, is_) in enumerate(zip(before.seen, now.seen, strict=True))
        if k != own and k in moved and was >= 0 and is_held(was) and is_ == NOT_IN_VIEW
    )
    return now if lost == now.lost else Percept(now.cell, now.seen, lost)


def told(p: Percept, item: int, value: int) -> Percept:
    """``p`` plus being told that ``item`` has ``value`` (speech overrides sight)."""
    seen = list(p.seen)
    seen[item] = value
    return Percept(cell=p.cell, seen=tuple(seen), lost=tuple(k for k in p.lost if k != item))


class BeliefModel:
    """Belief transitions of one world model (the ``(W, W, K)`` comparison table is built once)."""

    def __init__(self, model: WorldModel, r: float, delta: float) -> None:
        self.model = model
        self.r = r
        self.delta = delta

    @cached_property
    def bit(self) -> npt.NDArray[np.unsignedinteger]:
        """``(K,)`` the bit of each item in an item set packed into the smallest unsigned
        integer that holds ``K`` bits."""
        K = self.model.n_items
        dtype = next(t for t in (np.uint8, np.uint16, np.uint32, np.uint64) if np.iinfo(t).bits >= K)
        return np.left_shift(dtype(1), np.arange(K, dtype=dtype))

    @cached_property
    def differ(self) -> npt.NDArray[np.unsignedinteger]:
        """``(W, W)``: the set of items on which worlds ``i`` and ``j`` differ, as bits."""
        worlds = self.model.worlds
        bits = np.zeros((len(worlds), len(worlds)), dtype=self.bit.dtype)
        for k in range(self.model.n_items):  # K passes over (W, W), not a (W, W, K) array
            bits |= np.where(worlds[:, None, k] != worlds[None, :, k], self.bit[k], 0).astype(bits.dtype)
        return bits

    def percept_likelihood(self, p: Percept) -> FloatArray:
        """``(W,)`` ``P(o | x, w)`` for every world (0 for a world a location's capacity rules out)."""
        model = self.model
        visible = model.sees[p.cell]
        seen = np.array(p.seen)
        blind = (seen[None, :] == UNNOTICED) | ~visible[model.place]
        match = np.where(seen[None, :] >= 0, model.worlds == seen[None, :], blind)
        return np.prod(np.where(match, 1.0 - self.delta, self.delta), axis=1) * model.allowed

    def in_pw(self, p: Percept) -> npt.NDArray[np.bool_]:
        """``(W_i, W_j)`` whether ``i`` is in ``PW(j)``: it differs from ``j`` only in items the
        person at ``p.cell`` can see now (in view, or believed by ``j`` to be at a visible spot)."""
        anywhere = changes(self.model, p).anywhere
        changing = anywhere[np.arange(self.model.n_items)[None, :], self.model.worlds]  # (W_j, K)
        fixed = np.bitwise_or.reduce(np.where(changing, 0, self.bit), axis=1)  # (W_j,) must stay put
        return (self.differ & fixed[None, :]) == 0

    def redraw(self, p: Percept) -> FloatArray | None:
        """``(W_i, W_j)`` the redraw of the items the person just lost sight of in someone's
        hands (:meth:`Changes.redraw`, over whole worlds), or ``None`` when there is none."""
        ch = changes(self.model, p)
        if not ch.lost:
            return None
        u, worlds = ch.redraw(), self.model.worlds
        out = np.ones((len(worlds), len(worlds)))
        for k in range(self.model.n_items):
            out *= u[k][worlds[:, None, k], worlds[None, :, k]]
        return out

    def apply_change(self, beliefs: FloatArray, p: Percept, *, predict: bool) -> FloatArray:
        """``beliefs @ g.T`` for ``(N, W)`` beliefs, ``g`` the paper's change weights
        (:meth:`change_weights`), each column first normalised when ``predict``; without
        building ``g``. Whether item ``k`` of world ``j`` may change depends on its value
        alone (it is in view, or ``j`` puts it at a visible spot), so "``i`` is in ``PW(j)``"
        is a product over items of ``(V, V)`` matrices ``M_k[i_k, j_k]`` and the sum over
        ``j`` is one small matrix product per item axis of the ``(N, V, ..., V)`` tensor:
        ``O(N W V K)`` instead of ``O(N W^2)``. Returns a new array (callers may change it in
        place), never a view of ``beliefs``."""
        model = self.model
        K, V = model.n_items, model.n_values
        ch = changes(model, p)
        x = beliefs
        if ch.lost:  # first the redraw of what was carried off (columns of one: no normalising)
            x = redrawn(x.reshape(len(x), *([V] * K)), ch).reshape(len(x), -1)
        if predict:  # column j of g sums to 1 + r (|PW(j)| - 1)
            reach = np.where(ch.anywhere[np.arange(K)[None, :], model.worlds], float(V), 1.0).prod(axis=1)
            x = x / (1.0 + self.r * (reach - 1.0))[None, :]
        tensor = x.reshape(len(x), *([V] * K))
        fresh = False  # whether ``tensor`` is an array of our own (else a view of ``x``)
        for k in range(K):
            # M_k[i, j] is 1 for every i where value j may change, else only for i = j: so the
            # product is, at every value, the sum over the changeable values (one matrix-vector
            # product), plus the value's own mass where it cannot change
            movable = ch.anywhere[k]
            if not movable.any():
                continue
            total = np.tensordot(tensor, movable.astype(np.float64), axes=([1 + k], [0]))
            total = np.expand_dims(total, 1 + k)
            if movable.all():
                tensor = np.broadcast_to(total, tensor.shape).copy()
            else:  # the own mass where it cannot change (times 0 elsewhere: exactly the sum alone)
                stays = (~movable).astype(np.float64).reshape((1,) * (1 + k) + (V,) + (1,) * (K - 1 - k))
                tensor = tensor * stays
                tensor += total
            fresh = True
        changed = tensor.reshape(len(x), -1) if fresh else x.copy()
        changed *= self.r  # in place, one pass fewer: the same numbers as (1 - r) x + r tensor
        changed += (1.0 - self.r) * x
        return changed

    def change_weights(self, p: Percept) -> FloatArray:
        """``(W_i, W_j)`` the paper's ``g(i, j)``: 1 to stay, ``r`` for a change inside ``PW(j)``,
        0 outside."""
        g = np.where(self.in_pw(p), self.r, 0.0)
        np.fill_diagonal(g, 1.0)
        u = self.redraw(p)
        return g if u is None else g @ u

    def transition(self, p: Percept) -> FloatArray:
        """``(W, W)`` matrix ``T[i, j] = P(b_t = i | b_{t-1} = j, o_t)``; columns sum to 1, but
        for a world ``j`` the model rules out with no allowed world in reach (a fixed item
        held where the person cannot see it): all zero (no belief is ever there)."""
        likelihood = self.percept_likelihood(p)
        t = self.in_pw(p) * (self.r * likelihood)[:, None]
        np.fill_diagonal(t, likelihood)
        u = self.redraw(p)
        if u is not None:  # what was carried off is redrawn first
            t = t @ u
        total = t.sum(axis=0, keepdims=True)
        t /= np.where(total > 0, total, 1.0)
        return t

    def true_target(self, truth: tuple[int, ...], p: Percept) -> int:
        """The world an observer who assumes people know the true world puts them in."""
        values = np.array(truth)
        own = [k for k, v in enumerate(p.seen) if v >= 0 and is_held(v) and v != values[k]]
        for k in own:  # the person's own carried item counts at the person's location
            values[k] = p.seen[k]
        return int(self.model.world_index(values))

    def true_world(self, truth: tuple[int, ...], p: Percept) -> FloatArray:
        """``(W, W)`` transition of an observer who assumes people know the true world."""
        t = np.zeros((self.model.n_worlds, self.model.n_worlds))
        t[self.true_target(truth, p), :] = 1.0
        return t
