"""``toyroom eval``: random episodes with simulated people (:mod:`.episodes`), each run an
engine and a brain process (:mod:`.runs`), scored against the people's true minds
(:mod:`.metrics`, :mod:`.outcome`) and reported (:mod:`.report`), locally or on Ray."""

from .aggregate import aggregate
from .conditions import Condition
from .episodes import EpisodeJob, evaluate, run_episode
from .metrics import Counts, Outcome, score_tick
from .outcome import judge
from .runs import RunRecord, RunResult, RunSpec, run_once

__all__ = [
    "aggregate",
    "Condition",
    "EpisodeJob",
    "evaluate",
    "judge",
    "run_episode",
    "run_once",
    "score_tick",
    "Counts",
    "Outcome",
    "RunRecord",
    "RunResult",
    "RunSpec",
]
