"""``toyroom eval``: random episodes with simulated people (:mod:`.generation`,
:mod:`.episodes`), each run an engine and a brain (:mod:`.runs`; several episodes' runs
sharing the processes, :mod:`.batches`), scored against the people's true minds
(:mod:`.metrics`, :mod:`.outcome`) and reported (:mod:`.report`), locally or on Ray."""

from .aggregate import aggregate
from .batches import BatchResult, run_batch
from .conditions import Condition
from .episodes import EpisodeJob, evaluate, run_episode, run_episodes
from .generation import generate, generate_all, map_of
from .metrics import Counts, EpisodeOutcome, score_tick
from .outcome import judge
from .runs import RunRecord, RunResult, RunSpec, run_once
from .summary import ConditionSummary, Evaluation, HouseholdEvaluation, HouseholdSummary, Interval, Summary

__all__ = [
    "aggregate",
    "BatchResult",
    "generate",
    "generate_all",
    "map_of",
    "run_batch",
    "run_episodes",
    "Condition",
    "EpisodeJob",
    "evaluate",
    "judge",
    "run_episode",
    "run_once",
    "score_tick",
    "Counts",
    "EpisodeOutcome",
    "RunRecord",
    "RunResult",
    "RunSpec",
    "ConditionSummary",
    "Evaluation",
    "HouseholdEvaluation",
    "HouseholdSummary",
    "Interval",
    "Summary",
]
