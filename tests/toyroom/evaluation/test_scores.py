"""The metrics record (:class:`toyroom.evaluation.scores.Scores`) is the one list of metric
names: what counts compute, what gets an interval, and what each report table shows."""

from __future__ import annotations

from toyroom.evaluation import intervals, report
from toyroom.evaluation.metrics import Counts
from toyroom.evaluation.scores import MetricGroup, metric_names


def test_counts_compute_exactly_the_records_metrics() -> None:
    computed = list(Counts().metrics())
    assert computed == list(metric_names()), f"expected {list(metric_names())}, got {computed}"


def test_every_metric_is_in_one_report_table_and_intervals_follow_the_record() -> None:
    tables = (report.METRICS, report.BEHAVIOUR, report.NESTED, report.WANT)
    shown = [name for table in tables for name in table]
    assert sorted(shown) == sorted(metric_names()), f"each metric once in a table, got {shown}"
    assert intervals.METRICS == metric_names(interval=True)
    plain = set(metric_names(interval=False))
    assert plain == {
        "false_belief_precision",
        "false_belief_recall",
        "revealed_lead_median",
        "revealed_lead_any_median",
    }, f"a precision, a recall and the median leads are shown without intervals, got {plain}"
    assert report.WANT == metric_names(MetricGroup.WANT) == ("fb_want_p", "fb_want_confident", "fb_want_top")
