"""The log-likelihood of a recorded episode's decisions under a model: the brain's filter
run over the recording, its normalisers summed over people (``Estimate.log_evidence``)."""

from __future__ import annotations

from dataclasses import dataclass

from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from bridge.recording.trace import Trace
from protocol import Observer


@dataclass(frozen=True)
class Evidence:
    """One episode under one model: ``log_likelihood`` (natural log) of its ``actions``
    decisions, all people together."""

    log_likelihood: float
    actions: int


def episode_evidence(trace: Trace, settings: ModelSettings, observer: Observer = Observer.BTOM) -> Evidence:
    """Run a fresh tracker over ``trace`` and read every person's log-evidence and the
    number of decisions it sums over."""
    tracker = MindTracker(trace.info.scene, settings, observer=observer)
    for state, events in trace:
        tracker.observe(state, events)
    total, actions = 0.0, 0
    for person in tracker.people:
        total += tracker.log_evidence(person)
        chains = tracker.tracks[person].chains
        actions += sum(1 for record in chains[0].steps if record.likelihood is not None) if chains else 0
    return Evidence(total, actions)
