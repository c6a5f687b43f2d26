"""Scoring a brain against simulated people's true minds (pure functions).

Per tick, person and item, from the brain's online ``mind`` and the engine's ``truth``:

- ``belief_tv``: total-variation distance between the inferred and the true belief over
  the item's location, averaged;
- ``preference_accuracy``: the most probable inferred preference equals the true one,
  over ticks after the person first took an item (most of them a person playing with the
  very item they want: an observer without a theory of mind scores as well there);
- ``fb_want_p``, ``fb_want_confident``, ``fb_want_top``: the want read where help matters,
  over the ticks from a person's false belief about the item they want to their first take
  of it (:mod:`.wantread`): the mean P(true want), the share of those ticks at or above the
  robot's threshold, and how often the true want is the most probable goal (a tie of n: 1/n);
- false beliefs: the brain's flag against the truth that the person's true belief gives
  the item's true location less than :data:`~protocol.FALSE_BELIEF_MASS` times its likeliest
  location's (:func:`protocol.believes_falsely`, the brain's own rule: a belief spread over
  places that include the truth is ignorance, not a false belief, however many places; no
  tie is broken by the order of locations), as precision, recall and F1 (pooled over
  everything);
- the true preferences seen, so that a majority-class observer (always the most common
  preference, never a false belief) can be scored from the same counts;
- ``goal_false_belief_f1``: the same F1 over the beliefs about the item each person wants
  now (their true preference, when it is an item): the false beliefs behaviour can reveal
  and the robot's help depends on. A false belief about an item nobody is after shows in
  no action, so no observer can do better there than its prior;
- false beliefs by how they arose (:data:`CAUSES`, :func:`false_belief_causes`), each with
  its ticks and the ticks an observer flagged: what share of the false beliefs could be seen
  at all, and by whom;
- ``knowable_false_belief_f1``: the F1 over the false beliefs the robot could know of (caused
  by a move it perceived, or revealed by a pursuit: :mod:`toyroom.evaluation.revealed`); the
  other false beliefs count neither way, every tick without one is a negative;
- ``revealed_detection``: the share of revealed stretches the observer flagged before the
  person reached the place, and the median lead in ticks (:mod:`toyroom.evaluation.revealed`);
  ``revealed_detection_any``: the same, item-agnostic (the observer read the person as
  heading for a place where they falsely believe some wanted item rests, above 0.5);
- ``brier``, ``log_loss`` (probabilities clipped to ``[EPS, 1 - EPS]``) of the observer's
  P(false belief) over every person-item-tick, and ``brier_skill``: 1 - Brier / the Brier of
  always answering the base rate of these ticks (0: no better than the base rate).
"""

from __future__ import annotations

import math
import statistics
from collections.abc import Iterable, Mapping
from dataclasses import dataclass, field, fields

from protocol import Mind, Truth, believes_falsely

from .scoredminds import ScoredMind
from .scores import Scores
from .summary import CauseRecall
from .wantread import WantScore

EPS = 1e-3
"""Probabilities are clipped to ``[EPS, 1 - EPS]`` for the log loss (an observer that says 0
and is wrong pays ``-ln(EPS)`` = 6.9, not infinity)."""


CAUSES = ("start", "moved", "unmoved")
"""How a false belief arose, read off the truth at its first tick: ``start`` (held from the
person's first tick: a belief from before the episode), ``moved`` (the item changed place that
tick, unseen by the person: the classic false belief) or ``unmoved`` (the item stayed put and
the person's belief left it: what they were told, overlooked or forgot; nothing the robot
sees happen)."""


def false_belief_causes(truths: Mapping[int, Truth]) -> dict[int, dict[tuple[str, str], str]]:
    """Tick -> ``(person, item)`` -> the :data:`CAUSES` entry of each false belief held then
    (:func:`protocol.believes_falsely`), its cause fixed at its first tick."""
    out: dict[int, dict[tuple[str, str], str]] = {}
    current: dict[tuple[str, str], str] = {}
    before: dict[str, str] | None = None
    for tick in sorted(truths):
        truth = truths[tick]
        where = {place.item: place.location for place in truth.items}
        held: dict[tuple[str, str], str] = {}
        for person in truth.agents:
            for belief in person.beliefs:
                true = {p.id: p.p for p in belief.locations}
                place = where.get(belief.item)
                if place is None or not believes_falsely(true, place):
                    continue
                key = (person.agent, belief.item)
                if key in current:
                    held[key] = current[key]
                elif before is None:
                    held[key] = "start"
                else:
                    held[key] = "moved" if before.get(belief.item) != place else "unmoved"
        current, before = held, where
        out[tick] = held
    return out


@dataclass
class Counts:
    """Sums that add up across ticks, runs and episodes."""

    tv_sum: float = 0.0
    tv_n: int = 0
    pref_hits: int = 0
    pref_n: int = 0
    tp: int = 0
    fp: int = 0
    fn: int = 0
    tn: int = 0
    goal_tp: int = 0
    goal_fp: int = 0
    goal_fn: int = 0
    goal_tn: int = 0
    """The false-belief counts restricted to the item each person wants."""
    pref_truth: dict[str, int] = field(default_factory=dict)
    """How often each preference was the true one, over the ticks ``pref_n`` counts."""
    cause_fb: dict[str, int] = field(default_factory=dict)
    """False-belief ticks by how they arose (:data:`CAUSES`)."""
    cause_tp: dict[str, int] = field(default_factory=dict)
    """Of those, the ticks the observer flagged."""
    known_tp: int = 0
    known_fp: int = 0
    known_fn: int = 0
    known_tn: int = 0
    """The false-belief counts over knowable false beliefs and ticks without one."""
    brier_sum: float = 0.0
    log_loss_sum: float = 0.0
    prob_n: int = 0
    fb_n: int = 0
    """Sums of the squared error and log loss of P(false belief), person-item-ticks, and how
    many of them held a false belief."""
    stretches: int = 0
    detected: int = 0
    detected_any: int = 0
    leads: list[int] = field(default_factory=list)
    leads_any: list[int] = field(default_factory=list)
    """Revealed stretches, how many were detected in time (item by item, and item-agnostic:
    :func:`~toyroom.evaluation.revealed.detection_lead_any`), and each detection's lead
    (ticks)."""
    nested_n: int = 0
    nested_right: int = 0
    nested_first_right: int = 0
    """Nested beliefs that differ from the other's own (:mod:`.nestedscore`), how many the
    observer's nested estimate read right, and how many its first-order estimate did."""
    want_p_sum: float = 0.0
    want_confident: int = 0
    want_top_sum: float = 0.0
    want_n: int = 0
    """Over the person-ticks of want stretches (:mod:`.wantread`): the sum of P(true want),
    the ticks at or above the robot's threshold, the sum of top-goal hits (a tie of n: 1/n),
    and how many person-ticks."""

    def add(self, other: Counts) -> None:
        mine, theirs = self.__dict__, other.__dict__  # the same sums as getattr/setattr, faster
        for name in SUMS:
            mine[name] += theirs[name]
        for mine, theirs in (
            (self.pref_truth, other.pref_truth),
            (self.cause_fb, other.cause_fb),
            (self.cause_tp, other.cause_tp),
        ):
            for key, n in theirs.items():
                mine[key] = mine.get(key, 0) + n
        self.leads = [*self.leads, *other.leads]
        self.leads_any = [*self.leads_any, *other.leads_any]

    def recall_by_cause(self) -> dict[str, CauseRecall]:
        """Per cause of :data:`CAUSES`: its false-belief ticks, their share of all, and the
        observer's recall on them."""
        total = sum(self.cause_fb.values())
        out: dict[str, CauseRecall] = {}
        for cause in CAUSES:
            ticks, caught = self.cause_fb.get(cause, 0), self.cause_tp.get(cause, 0)
            out[cause] = CauseRecall(
                ticks=ticks,
                share=ticks / total if total else None,
                recall=caught / ticks if ticks else None,
            )
        return out

    def majority(self) -> Counts:
        """:func:`majority_counts` with the most common true preference of these counts."""
        goal = max(self.pref_truth, key=lambda g: (self.pref_truth[g], g), default="")
        return majority_counts(self, goal)

    def metrics(self) -> dict[str, float | None]:
        """:meth:`scores` as metric name -> value."""
        return self.scores().as_dict()

    def scores(self) -> Scores:
        """The pooled metrics of these counts (:class:`~toyroom.evaluation.scores.Scores`)."""
        precision, recall, f1 = _f1(self.tp, self.fp, self.fn)
        return Scores(
            **{
                "belief_tv": self.tv_sum / self.tv_n if self.tv_n else None,
                "preference_accuracy": self.pref_hits / self.pref_n if self.pref_n else None,
                "false_belief_precision": precision,
                "false_belief_recall": recall,
                "false_belief_f1": f1,
                "goal_false_belief_f1": _f1(self.goal_tp, self.goal_fp, self.goal_fn)[2],
                "knowable_false_belief_f1": _f1(self.known_tp, self.known_fp, self.known_fn)[2],
                "revealed_detection": self.detected / self.stretches if self.stretches else None,
                "revealed_lead_median": float(statistics.median(self.leads)) if self.leads else None,
                "revealed_detection_any": self.detected_any / self.stretches if self.stretches else None,
                "revealed_lead_any_median": float(statistics.median(self.leads_any))
                if self.leads_any
                else None,
                **self.nested_scores(),
                **self.proper_scores(),
                **self.want_scores(),
            }
        )

    def want_scores(self) -> dict[str, float | None]:
        """``fb_want_p``, ``fb_want_confident`` and ``fb_want_top`` over the want stretches."""
        if not self.want_n:
            return {"fb_want_p": None, "fb_want_confident": None, "fb_want_top": None}
        return {
            "fb_want_p": self.want_p_sum / self.want_n,
            "fb_want_confident": self.want_confident / self.want_n,
            "fb_want_top": self.want_top_sum / self.want_n,
        }

    def add_want(self, scores: Iterable[WantScore]) -> None:
        """Count each person-tick's reading of the want (:func:`.wantread.score_want`)."""
        for score in scores:
            self.want_p_sum += score.p
            self.want_confident += score.confident
            self.want_top_sum += score.top
            self.want_n += 1

    def nested_scores(self) -> dict[str, float | None]:
        """``nested_belief_accuracy``, its first-order baseline's, and the difference."""
        if not self.nested_n:
            return {"nested_belief_accuracy": None, "nested_first_order_accuracy": None, "nested_gain": None}
        right, first = self.nested_right / self.nested_n, self.nested_first_right / self.nested_n
        return {
            "nested_belief_accuracy": right,
            "nested_first_order_accuracy": first,
            "nested_gain": right - first,
        }

    def proper_scores(self) -> dict[str, float | None]:
        """``brier``, ``log_loss`` and ``brier_skill`` (against the base rate of these ticks)."""
        if not self.prob_n:
            return {"brier": None, "log_loss": None, "brier_skill": None}
        brier, rate = self.brier_sum / self.prob_n, self.fb_n / self.prob_n
        reference = rate * (1.0 - rate)
        return {
            "brier": brier,
            "log_loss": self.log_loss_sum / self.prob_n,
            "brier_skill": 1.0 - brier / reference if reference > 0 else None,
        }

    def add_probability(self, p: float, actual: bool) -> None:
        """One person-item-tick's P(false belief) ``p`` against the truth."""
        q = min(max(p, EPS), 1.0 - EPS)
        self.brier_sum += (p - actual) ** 2
        self.log_loss_sum -= math.log(q if actual else 1.0 - q)
        self.prob_n += 1
        self.fb_n += actual


SUMS = tuple(f.name for f in fields(Counts) if isinstance(f.default, int | float))
"""The fields of :class:`Counts` that add up: the numbers (in their order), not the tallies
by key (``pref_truth``, ``cause_fb``, ``cause_tp``) nor ``leads`` and ``leads_any``, which
:meth:`Counts.add` merges itself."""


def _f1(tp: int, fp: int, fn: int) -> tuple[float | None, float | None, float | None]:
    """``(precision, recall, F1)``; F1 is 0 when false beliefs happened and none was caught
    (or flagged), ``None`` when there was nothing to catch and nothing was flagged."""
    precision = tp / (tp + fp) if tp + fp else None
    recall = tp / (tp + fn) if tp + fn else None
    if recall is not None and tp == 0:
        return precision, recall, 0.0
    if precision is not None and recall is not None:
        return precision, recall, 2 * precision * recall / (precision + recall)
    return precision, recall, None


def majority_counts(counts: Counts, goal: str) -> Counts:
    """The counts of a majority-class observer on the ticks of ``counts``: always ``goal``
    (the most common true preference), never a false belief (P(false belief) 0), no belief
    (``belief_tv``: none)."""
    positives, negatives = counts.tp + counts.fn, counts.fp + counts.tn
    never = -math.log(1.0 - EPS)
    return Counts(
        known_fn=counts.known_tp + counts.known_fn,
        known_tn=counts.known_fp + counts.known_tn,
        brier_sum=float(counts.fb_n),
        log_loss_sum=counts.fb_n * -math.log(EPS) + (counts.prob_n - counts.fb_n) * never,
        prob_n=counts.prob_n,
        fb_n=counts.fb_n,
        stretches=counts.stretches,
        pref_hits=counts.pref_truth.get(goal, 0),
        pref_n=counts.pref_n,
        fn=positives,
        tn=negatives,
        goal_fn=counts.goal_tp + counts.goal_fn,
        goal_tn=counts.goal_fp + counts.goal_tn,
        cause_fb=dict(counts.cause_fb),
    )


def score_tick(
    mind: Mind | ScoredMind,
    truth: Truth,
    true_location: dict[str, str],
    took: set[str],
    causes: Mapping[tuple[str, str], str] | None = None,
    known: set[tuple[str, str]] | None = None,
) -> Counts:
    """Score one tick.

    Args:
        mind: the brain's online estimates at this tick.
        truth: the people's true minds at this tick.
        true_location: where each item is now (a carried item at its carrier's location).
        took: people who have taken an item by now (preference accuracy counts from then on).
        causes: how each false belief held now arose (:func:`false_belief_causes`; none:
            not counted by cause).
        known: the false beliefs the robot could know of now
            (:func:`toyroom.evaluation.revealed.knowable`; none: all of them).
    """
    counts = Counts()
    estimates = {a.agent: a for a in mind.agents}
    for person in truth.agents:
        est = estimates.get(person.agent)
        if est is None:
            continue
        inferred = {b.item: {p.id: p.p for p in b.locations} for b in est.beliefs}
        chances = {p.id: p.p for p in est.false_belief}
        for belief in person.beliefs:
            true = {p.id: p.p for p in belief.locations}
            guess = inferred.get(belief.item, {})
            counts.tv_sum += 0.5 * sum(
                abs(true.get(loc, 0.0) - guess.get(loc, 0.0)) for loc in sorted(set(true) | set(guess))
            )
            counts.tv_n += 1
            where = true_location.get(belief.item)
            actual = where is not None and believes_falsely(true, where)
            flagged = belief.item in est.false_beliefs
            cause = (causes or {}).get((person.agent, belief.item)) if actual else None
            if cause is not None:
                counts.cause_fb[cause] = counts.cause_fb.get(cause, 0) + 1
                counts.cause_tp[cause] = counts.cause_tp.get(cause, 0) + flagged
            cell = ("tp" if flagged else "fn") if actual else ("fp" if flagged else "tn")
            names = [cell, *((f"goal_{cell}",) if belief.item == person.preference else ())]
            if not actual or known is None or (person.agent, belief.item) in known:
                names.append(f"known_{cell}")
            for name in names:
                setattr(counts, name, getattr(counts, name) + 1)
            counts.add_probability(chances.get(belief.item, float(flagged)), actual)
        if person.agent in took and est.preference:
            weights = [p.p for p in est.preference]
            best = est.preference[weights.index(max(weights))].id  # the first of the most probable
            counts.pref_n += 1
            counts.pref_hits += best == person.preference
            counts.pref_truth[person.preference] = counts.pref_truth.get(person.preference, 0) + 1
    return counts


@dataclass
class EpisodeOutcome:
    """How an episode ended for its people: whether each got what they wanted."""

    successes: int = 0
    people: int = 0
    per_person: dict[str, bool] = field(default_factory=dict)
    ticks_to_goal: dict[str, int | None] = field(default_factory=dict)
    """Per person, the first tick they played with the item they want at the end (or went
    outside, if they want to leave); ``None``: never."""
    ticks: int = 0
    """The episode's last tick."""

    @property
    def rate(self) -> float | None:
        return self.successes / self.people if self.people else None
