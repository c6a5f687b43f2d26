"""What the brain writes: the ``brain/mind`` message, ``mind.csv``, the figures and
``report.md`` (with the paper's ground truth where a scenario has one), and the minds of
shadow observers run on the same ticks (``minds-<observer>.jsonl``), and a run's log for
scoring it afterwards (``inputs.jsonl`` with the live minds)."""

from .groundtruth import GroundTruth, TruthStep, load_ground_truth
from .mindtable import MindRow, mind_rows, write_csv
from .report import write_report
from .results import mind_message, write_outputs
from .runlog import RunLog, inputs_path
from .shadows import ShadowMinds, shadow_path

__all__ = [
    "load_ground_truth",
    "mind_message",
    "mind_rows",
    "write_csv",
    "write_outputs",
    "shadow_path",
    "inputs_path",
    "write_report",
    "GroundTruth",
    "ShadowMinds",
    "RunLog",
    "MindRow",
    "TruthStep",
]
