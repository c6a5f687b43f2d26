"""``toyroom eval``: random episodes with simulated people (:mod:`.episodes`), each run an
engine and a brain process (:mod:`.runs`), scored against the people's true minds
(:mod:`.metrics`, :mod:`.outcome`) and reported (:mod:`.report`), locally or on Ray."""

from .episodes import aggregate, evaluate, run_episode
from .metrics import Counts, Outcome, score_tick
from .outcome import judge
from .runs import RunRecord, RunResult, RunSpec, run_once

__all__ = [
    "aggregate",
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
