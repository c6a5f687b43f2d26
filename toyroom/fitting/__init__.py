"""Fitting the model to recorded behaviour (``toyroom fit``): grids of parameters, the
log-likelihood of an episode's decisions, k-fold cross-validation by episode and the model
comparison by held-out log-likelihood per action (and, given people's ratings, by
correlation with them), and the optimiser that refines the grid's best point
(``--refine``)."""

from .crossval import Fold, cross_validate, folds, held_out_per_action
from .evidence import Evidence, episode_evidence
from .fit import ModelFit, fit, write_fit
from .grid import GRIDS, parse_grid, points
from .motion import MOTION, motion_evidence, motion_predictions
from .optimise import BOUNDS, Bound, Refinement, refine
from .search import BRAIN_MODELS, DEFAULT_MODELS, MODELS, ModelSpec, Table, search

__all__ = [
    "BOUNDS",
    "BRAIN_MODELS",
    "Bound",
    "DEFAULT_MODELS",
    "GRIDS",
    "MODELS",
    "MOTION",
    "ModelSpec",
    "Evidence",
    "Fold",
    "ModelFit",
    "Refinement",
    "Table",
    "cross_validate",
    "episode_evidence",
    "fit",
    "folds",
    "held_out_per_action",
    "motion_evidence",
    "motion_predictions",
    "parse_grid",
    "points",
    "refine",
    "search",
    "write_fit",
]
