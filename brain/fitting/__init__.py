"""Fitting the model to recorded behaviour (``toyroom fit``): grids of parameters, the
log-likelihood of an episode's decisions, k-fold cross-validation by episode and the model
comparison by held-out log-likelihood per action."""

from .crossval import Fold, cross_validate, folds, held_out_per_action
from .evidence import Evidence, episode_evidence
from .fit import ModelFit, fit, write_fit
from .grid import GRIDS, parse_grid, points
from .search import DEFAULT_MODELS, MODELS, Table, search

__all__ = [
    "DEFAULT_MODELS",
    "GRIDS",
    "MODELS",
    "Evidence",
    "Fold",
    "ModelFit",
    "Table",
    "cross_validate",
    "episode_evidence",
    "fit",
    "folds",
    "held_out_per_action",
    "parse_grid",
    "points",
    "search",
    "write_fit",
]
