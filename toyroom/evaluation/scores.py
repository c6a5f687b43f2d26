"""The evaluation's metrics as one typed record (:class:`Scores`): its fields are the metric
names everywhere, in ``metrics.json``, the report's tables, the bootstrap intervals and the
tests, so a metric is added in one place. Each field says which table it belongs in
(:class:`MetricGroup`) and whether it gets a paired bootstrap interval (a pooled share or
mean does; a precision, a recall and a median lead are shown as they are)."""

from __future__ import annotations

import dataclasses
import enum
from dataclasses import dataclass
from typing import Any


class MetricGroup(enum.Enum):
    """The report table a metric is shown in."""

    BELIEFS = "beliefs"
    """Beliefs, the want after a first take, and false beliefs (the first table)."""
    BEHAVIOUR = "behaviour"
    """False beliefs where they can be known, and the proper scores of P(false belief)."""
    NESTED = "nested"
    """What each person believes the others believe."""
    WANT = "want"
    """The want read over false-belief stretches (issue 65)."""


def _metric(group: MetricGroup, interval: bool = True) -> Any:
    return dataclasses.field(default=None, metadata={"group": group, "interval": interval})


@dataclass(frozen=True)
class Scores:
    """One observer's pooled metrics (``None`` where nothing was scored); definitions in
    :mod:`toyroom.evaluation.metrics`. Shares and distances are in [0, 1], leads in ticks."""

    belief_tv: float | None = _metric(MetricGroup.BELIEFS)
    preference_accuracy: float | None = _metric(MetricGroup.BELIEFS)
    false_belief_precision: float | None = _metric(MetricGroup.BELIEFS, interval=False)
    false_belief_recall: float | None = _metric(MetricGroup.BELIEFS, interval=False)
    false_belief_f1: float | None = _metric(MetricGroup.BELIEFS)
    goal_false_belief_f1: float | None = _metric(MetricGroup.BELIEFS)
    knowable_false_belief_f1: float | None = _metric(MetricGroup.BEHAVIOUR)
    revealed_detection: float | None = _metric(MetricGroup.BEHAVIOUR)
    revealed_lead_median: float | None = _metric(MetricGroup.BEHAVIOUR, interval=False)
    revealed_detection_any: float | None = _metric(MetricGroup.BEHAVIOUR)
    revealed_lead_any_median: float | None = _metric(MetricGroup.BEHAVIOUR, interval=False)
    brier: float | None = _metric(MetricGroup.BEHAVIOUR)
    log_loss: float | None = _metric(MetricGroup.BEHAVIOUR)
    brier_skill: float | None = _metric(MetricGroup.BEHAVIOUR)
    nested_belief_accuracy: float | None = _metric(MetricGroup.NESTED)
    nested_first_order_accuracy: float | None = _metric(MetricGroup.NESTED)
    nested_gain: float | None = _metric(MetricGroup.NESTED)
    fb_want_p: float | None = _metric(MetricGroup.WANT)
    fb_want_confident: float | None = _metric(MetricGroup.WANT)
    fb_want_top: float | None = _metric(MetricGroup.WANT)

    def as_dict(self) -> dict[str, float | None]:
        """Metric name -> value, in the record's order (as ``metrics.json`` writes them)."""
        return dataclasses.asdict(self)


def metric_names(group: MetricGroup | None = None, *, interval: bool | None = None) -> tuple[str, ...]:
    """The metric names of :class:`Scores`, in its order: those of ``group`` (all: ``None``),
    and with ``interval``, only those that do (``True``) or do not (``False``) get one."""
    return tuple(
        f.name
        for f in dataclasses.fields(Scores)
        if (group is None or f.metadata["group"] is group)
        and (interval is None or f.metadata["interval"] is interval)
    )
