"""The model's pure math (numpy arrays in, arrays out; no I/O, no bridge): the world as
indexed arrays, each person's belief update from percepts, the Boltzmann planner, the HMM's
forward and backward passes, the factored model of large houses, and the estimates read off
a posterior; one person's filter in each of its forms, on that math, in its own room
(:mod:`brain.model.person`)."""

from .arrays import BoolArray, FloatArray, IntArray
from .belief import BeliefModel, Percept, percept, told, true_values
from .desires import RATING_SCALE, DesireSummary, goal_scale, on_scale
from .estimates import OUT, Estimate, estimate, false_belief_probability, reread
from .inference import HmmStep, forward, forward_step, smooth, switch_probability
from .person import ExactModel, FactoredModel, PersonFilter, PersonModel, StepRecord, person_model
from .planner import TAKE, Move, PlanPolicy, cached_policy, plan
from .revisions import SharedRevisions
from .world import MOVE_STEPS, WorldModel, build_world_model

__all__ = [
    "MOVE_STEPS",
    "OUT",
    "RATING_SCALE",
    "TAKE",
    "build_world_model",
    "cached_policy",
    "estimate",
    "false_belief_probability",
    "reread",
    "forward",
    "forward_step",
    "goal_scale",
    "on_scale",
    "percept",
    "person_model",
    "plan",
    "smooth",
    "switch_probability",
    "told",
    "true_values",
    "BeliefModel",
    "BoolArray",
    "DesireSummary",
    "Estimate",
    "ExactModel",
    "FactoredModel",
    "FloatArray",
    "HmmStep",
    "IntArray",
    "Move",
    "Percept",
    "PersonFilter",
    "PersonModel",
    "PlanPolicy",
    "SharedRevisions",
    "StepRecord",
    "WorldModel",
]
