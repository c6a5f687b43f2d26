"""Following every person of a scene tick by tick: :class:`MindTracker` (one observer's
estimates, online and smoothed)."""

from .tracker import MindTracker, PersonTrack

__all__ = [
    "MindTracker",
    "PersonTrack",
]
