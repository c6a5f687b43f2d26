"""The memory a scene's model takes, computed from its sizes before anything is allocated,
and the bound the brain keeps to (:data:`MAX_MODEL_BYTES`).

Sizes (``docs/model.md``): ``C`` walkable cells, ``L`` item locations (and ``absent``),
``K`` items, ``V = 2 L``, ``W = V**K`` worlds, ``A`` actions, ``U`` candidate desires,
``P`` hypotheses of one item's initial belief (graded), ``G = P**K``. The figure counts the
largest arrays of the model the settings pick (``exact_max_worlds``, ``belief_model``),
float64 unless said: the exact model's ``(U, S, A)`` Q-values and likelihoods and its
``(S, A)`` transitions (``S = C (K+1) W``) and, graded, its ``(G, W)`` beliefs; the factored
model's ``(D, C, 3, V, A)`` Q-values and likelihoods and, graded, its ``(K, P, V)`` beliefs.
"""

from __future__ import annotations

from dataclasses import dataclass
from math import comb

from protocol import AgentKind, RegionKind, Scene

from ..errors import ModelTooLarge
from ..settings import ModelSettings
from .person.lapses import lapse_rows
from .planner import n_actions
from .world import VALUES_PER_LOCATION

MAX_MODEL_BYTES = 2 * 2**30
"""2 GiB: the most the model's arrays of one scene may take. ``toyroom bench``'s largest
house (20 rooms, 10 items, 8 people) needs about 75 MB, the paper map's exact graded model
about 30 MB; a brain process holds a model per observer (shadows too), so a larger scene
would crowd out a laptop's memory rather than run."""


MEMORY_BUDGET_GB = 2.0
"""The resident memory (GiB) a brain process keeps to with lapses (``miss``) and an embodied
robot on the bundled houses, measured by ``toyroom bench --memory``; the tracker refuses a
scene whose branches of the unseen world, people and lapse rows could not fit in it even at
their smallest (:func:`check_tracking_size`)."""


@dataclass(frozen=True)
class ModelSize:
    """A scene's model: which form, how many bytes, and the product that gives them."""

    form: str
    bytes: int
    how: str


def grid_points(n_locations: int, resolution: int, ignorance: float) -> int:
    """``P``: the grid's points over ``n_locations`` at ``resolution``, and the uniform
    belief when ``ignorance > 0`` (:func:`brain.model.graded.initial_points`; at most one more)."""
    return comb(n_locations + resolution - 1, resolution) + (1 if ignorance > 0 else 0)


def _candidates(settings: ModelSettings, n_items: int, leaves: bool) -> int:
    """``U``: candidate desires (:func:`brain.model.desires.utilities`)."""
    goals = n_items + 1
    if settings.desire_model == "graded":
        return settings.desire_levels ** (goals if leaves else n_items) - 1
    return goals


def model_size(scene: Scene, settings: ModelSettings) -> ModelSize:
    """The memory the model of ``scene`` under ``settings`` takes (see the module's note)."""
    C = len(scene.walkable())
    L = len(scene.locations) + any(item.absent for item in scene.items)
    K, V = len(scene.items), VALUES_PER_LOCATION * L
    A, W = n_actions(K), V**K
    graded = settings.belief_model == "graded"
    P = grid_points(L, settings.prior_resolution, settings.ignorance) if graded else 0
    if W > settings.exact_max_worlds:
        size = 2 * (K + 1) * C * 3 * V * A * 8 + 2 * K * P * V * 8
        how = f"factored: 2 x {K + 1} preferences x {C} cells x 3 x {V} values x {A} actions"
        return ModelSize(
            "factored", size, how + (f" + 2 x {K} items x {P} hypotheses x {V}" if graded else "")
        )
    leaves = any(r.kind == RegionKind.OUTSIDE for r in scene.regions)
    U, S = _candidates(settings, K, leaves), C * (K + 1) * W
    size = S * A * (16 * U + 9) + (3 * P**K * W * 8 if graded else 0)
    how = f"exact: {C} cells x {K + 1} x {W} worlds x {A} actions x {U} desires"
    return ModelSize("exact", size, how + (f" + 3 x {P}^{K} hypotheses x {W} worlds" if graded else ""))


def check_model_size(scene: Scene, settings: ModelSettings) -> ModelSize:
    """``scene``'s model size, once it is within :data:`MAX_MODEL_BYTES`.

    Raises:
        ModelTooLarge: one line naming the scene, the bytes, how they come about and the limit.
    """
    size = model_size(scene, settings)
    if size.bytes > MAX_MODEL_BYTES:
        raise ModelTooLarge(
            f"scene '{scene.name}': the model's arrays would take {size.bytes / 2**30:.3g} GiB "
            f"({size.how}, 8 bytes each), above the brain's limit of {MAX_MODEL_BYTES / 2**30:.0f} GiB "
            "(MAX_MODEL_BYTES): fewer cells, item spots or items"
        )
    return size


def row_floor(scene: Scene, settings: ModelSettings) -> int:
    """The fewest bytes one filter row of one person holds (a lower bound: the factored
    rows are these arrays, 17.8 kB on an 8-room house and 53 kB on a 12-room one as measured;
    an exact graded row on ``house-b`` holds 724 kB against its 57 kB). Factored: its
    ``(K + 1) x K x V`` beliefs per preference, graded the ``(K + 1) x K x P`` weights and
    ``K x P x V`` beliefs of its hypotheses; exact: the
    ``(G, U)`` posterior and the ``G + W`` of a one-component mixture of beliefs, graded, or
    the ``(W, U)`` posterior."""
    L = len(scene.locations) + any(item.absent for item in scene.items)
    K, V = len(scene.items), VALUES_PER_LOCATION * L
    W, graded = V**K, settings.belief_model == "graded"
    P = grid_points(L, settings.prior_resolution, settings.ignorance) if graded else 0
    if W > settings.exact_max_worlds:
        return ((K + 1) * K * P + K * P * V if graded else (K + 1) * K * V) * 8
    U = _candidates(settings, K, any(r.kind == RegionKind.OUTSIDE for r in scene.regions))
    return (P**K * U + P**K + W if graded else W * U) * 8


def check_tracking_size(scene: Scene, settings: ModelSettings, branches: int, model: object) -> None:
    """Refuse a scene whose filters could not fit in :data:`MEMORY_BUDGET_GB` even at their
    smallest: ``branches`` of the robot's unseen world, times its people, times the rows of a
    person's filter under ``model`` (:func:`~brain.model.person.lapses.lapse_rows`: with lapses, up to
    ``LAPSE_ROWS + UNTESTED_ROWS``), times :func:`row_floor`.

    Raises:
        ModelTooLarge: one line naming the scene, each factor, the total and the budget.
    """
    people, rows = sum(1 for a in scene.agents if a.kind is AgentKind.PERSON), lapse_rows(model)
    floor = row_floor(scene, settings)
    need = branches * people * rows * floor
    if need > MEMORY_BUDGET_GB * 2**30:
        raise ModelTooLarge(
            f"scene '{scene.name}': {branches} branches of the unseen world x {people} people x "
            f"{rows} lapse rows x at least {floor / 2**20:.2f} MiB per row would take "
            f"{need / 2**30:.3g} GiB, above the brain's budget of {MEMORY_BUDGET_GB:.0f} GiB "
            "(MEMORY_BUDGET_GB): turn lapses off (miss = 0, hearsay_per_s = 0) or let the robot see "
            "more (perception = omniscient)"
        )


EXACT_MAX_BRANCHES = 512
"""The most branches of an embodied robot's unseen world left after its first look for which
``unseen_world = auto`` keeps the joint branches (:mod:`brain.tracking.jointworld`): above
it the factored world (:mod:`brain.tracking.itemworld`). A 12-room house with 3 items (1000
branches at the first look) ran with the joint branches, its first look taking about 70 s;
the bundled houses have at most 64."""

JOINT_MAX_WORLDS = 2**20
"""The most worlds ``W = V**K`` whose joint branches ``unseen_world = auto`` builds to look
with (the rows are every resting world of them): above it, the factored world from the start."""


def joint_branches(scene: Scene) -> int:
    """``H``: the branches of an embodied robot's unseen world before its first look, every
    item at every location (an absent one at ``absent`` alone; capacities not counted)."""
    L = len(scene.locations) + any(item.absent for item in scene.items)
    out = 1
    for item in scene.items:
        out *= 1 if item.absent else L
    return out


def factored_rows(scene: Scene, settings: ModelSettings, model: object, most: int) -> int:
    """The rows per person the factored unseen world keeps (:mod:`brain.tracking.personrows`):
    ``most``, or fewer so that the rows times the people times the lapse rows times
    :func:`row_floor` fit :data:`MEMORY_BUDGET_GB`.

    Raises:
        ModelTooLarge: not even one row per person fits (the omniscient robot's floor).
    """
    people, rows = sum(1 for a in scene.agents if a.kind is AgentKind.PERSON), lapse_rows(model)
    floor = row_floor(scene, settings)
    per_row = max(people * rows * floor, 1)
    fit = int(MEMORY_BUDGET_GB * 2**30 // per_row)
    if fit < 1:
        raise ModelTooLarge(
            f"scene '{scene.name}': {people} people x {rows} lapse rows x at least "
            f"{floor / 2**20:.2f} MiB per row would take {per_row / 2**30:.3g} GiB even with one row "
            f"of the unseen world each, above the brain's budget of {MEMORY_BUDGET_GB:.0f} GiB "
            "(MEMORY_BUDGET_GB): turn lapses off (miss = 0, hearsay_per_s = 0)"
        )
    return min(most, fit)
