"""Belief revisions shared by the person models of one brain that revise alike.

An observing brain runs ``btom`` live and ``perceptonly`` as a shadow on the same ticks
(:mod:`brain.outputs.shadows`). Both follow each person's percepts with the same graded
revision (:meth:`brain.model.person.gradedperson.GradedModel.revise`); they differ only in how
they weigh the hypotheses (``perceptonly`` reads no decisions). The revision is most of
either's cost on the evaluation houses (``(G, W)`` = ``(1331, 512)`` per person and branch),
so the second model takes the first's result instead of computing it again: bit for bit
the same array, since the same function of the same input (the input is the very array the
first model revised, or, at the first step, the shared prior).

The memo holds one tick's revisions (the models of a brain take each tick in turn), keyed
by what the revision reads: the models' revision settings, the tick, the percept and the
forgetting; it holds the arrays revised only weakly, so it keeps no memory alive that the
models let go. Arrays handed out are read-only, so no model can change another's beliefs.
An embodied robot's branches share too: the branches of one person start from the same
prior and revise alike while the percepts they imply agree. What is read off a shared array
alone (each item's marginal under every hypothesis, :meth:`read`) is shared the same way.
Pure numpy; no I/O.
"""

from __future__ import annotations

import weakref
from collections.abc import Callable, Hashable
from dataclasses import dataclass, field

import numpy as np

from .arrays import FloatArray
from .belief import Percept
from .mixture import Beliefs

Revise = Callable[[Beliefs], Beliefs]
Read = Callable[[Beliefs], FloatArray]


@dataclass
class SharedRevisions:
    """The memo (one per brain; pass it to every tracker that may share).

    Attributes:
        hits: revisions taken from the memo.
        misses: revisions computed (and kept for the others).
    """

    hits: int = 0
    misses: int = 0
    _tick: int | None = None
    _done: dict[Hashable, list[tuple[weakref.ref[Beliefs], Beliefs]]] = field(default_factory=dict)
    _initial: dict[Hashable, Beliefs] = field(default_factory=dict)
    _read: dict[Hashable, tuple[weakref.ref[Beliefs], FloatArray]] = field(default_factory=dict)

    def initial(self, key: Hashable, beliefs: Beliefs) -> Beliefs:
        """The prior ``(G, W)`` beliefs (or their read-only mixture) every model of revision
        settings ``key`` starts from: the first one's, read-only (so revisions of it can be
        recognised by identity)."""
        if key not in self._initial:
            shared = beliefs
            if isinstance(shared, np.ndarray):
                shared = shared.copy()
                shared.flags.writeable = False
            self._initial[key] = shared
        return self._initial[key]

    def revise(
        self, key: Hashable, tick: int, percept: Percept, forget: float, beliefs: Beliefs, compute: Revise
    ) -> Beliefs:
        """``compute(beliefs)`` for a model of revision settings ``key`` at ``tick``, or the
        same array another model computed from this very ``beliefs`` array this tick."""
        if tick != self._tick:
            self._tick, self._done = tick, {}
        done = self._done.setdefault((key, percept, forget), [])
        for before, after in done:
            if before() is beliefs:
                self.hits += 1
                return after
        after = compute(beliefs)
        if isinstance(after, np.ndarray):  # a mixture is read-only already
            after.flags.writeable = False
        done.append((weakref.ref(beliefs), after))  # the memo keeps no belief alive that its models let go
        self.misses += 1
        return after

    def read(self, key: Hashable, beliefs: Beliefs, compute: Read) -> FloatArray:
        """``compute(beliefs)`` for something read off a shared belief array alone (a model's
        marginals, ``key`` naming what and under which settings), or the array another model
        computed from this very array: the last one is kept per ``key`` (weakly, read-only)."""
        kept = self._read.get(key)
        if kept is not None and kept[0]() is beliefs:
            return kept[1]
        out = compute(beliefs)
        out.flags.writeable = False
        self._read[key] = (weakref.ref(beliefs), out)
        return out
