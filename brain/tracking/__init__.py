"""Following every person of a scene tick by tick: :class:`MindTracker` (one observer's
estimates, online and smoothed)."""

from .track import PersonTrack
from .tracker import MindTracker

__all__ = [
    "MindTracker",
    "PersonTrack",
]
