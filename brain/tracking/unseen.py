"""Which unseen world an embodied robot keeps (``ModelSettings.unseen_world``): the joint
branches (:mod:`brain.tracking.jointworld`, exact) where they fit, the factored world
(:mod:`brain.tracking.itemworld`) above. ``auto`` builds the joint branches while the scene
has at most :data:`~brain.model.size.JOINT_MAX_WORLDS` worlds, and keeps them at the robot's
first look (before any filter is made) while at most
:data:`~brain.model.size.EXACT_MAX_BRANCHES` are left and they fit the memory budget
(:func:`~brain.model.size.check_tracking_size`); else the factored world, which is logged.
Pure; no I/O.
"""

from __future__ import annotations

import logging
from collections.abc import Sequence

import msgspec

from protocol import Scene, State

from ..errors import ModelTooLarge
from ..model.arrays import IntArray
from ..model.person.personinterface import PersonModel
from ..model.size import (
    EXACT_MAX_BRANCHES,
    JOINT_MAX_WORLDS,
    check_tracking_size,
    factored_rows,
    joint_branches,
)
from ..model.world import WorldModel
from ..settings import ModelSettings, UnseenWorld
from .itemview import ItemView
from .itemworld import ItemWorld
from .jointworld import Evidence, JointWorld
from .personrows import MAX_ROWS, ROWS_IN_ALL
from .worldview import WorldView

log = logging.getLogger("toyroom.brain")

Unseen = JointWorld | ItemWorld


def unseen_world(
    scene: Scene,
    settings: ModelSettings,
    person_model: PersonModel,
    people: Sequence[str],
    evidence: Evidence,
) -> Unseen:
    """The unseen world ``settings.unseen_world`` picks for ``scene`` (see the module's note).

    Raises:
        ModelTooLarge: ``factored``, and not one row per person fits the memory budget.
    """
    choice = settings.unseen_world
    if choice is UnseenWorld.AUTO:
        fits = person_model.model.n_worlds <= JOINT_MAX_WORLDS
        choice = UnseenWorld.JOINT if fits else UnseenWorld.FACTORED
    absent = [k for k, item in enumerate(scene.items) if item.absent]
    if choice is UnseenWorld.JOINT:
        return JointWorld(WorldView(person_model.model, absent), people, evidence)
    return factored_world(scene, settings, person_model, people, evidence)


def factored_world(
    scene: Scene,
    settings: ModelSettings,
    person_model: PersonModel,
    people: Sequence[str],
    evidence: Evidence,
) -> ItemWorld:
    """The factored world, with as many rows per person as fit (:func:`~brain.model.size.factored_rows`)."""
    absent = [k for k, item in enumerate(scene.items) if item.absent]
    most = min(MAX_ROWS, max(1, ROWS_IN_ALL // max(1, len(people))))
    cap = factored_rows(scene, settings, person_model, most)
    log.info(
        "scene '%s': the factored unseen world (%d joint branches; up to %d rows per person)",
        scene.name,
        joint_branches(scene),
        cap,
    )
    return ItemWorld(ItemView(person_model.model, absent), people, evidence, cap)


def checked(
    world: Unseen,
    scene: Scene,
    settings: ModelSettings,
    person_model: PersonModel,
    people: Sequence[str],
    evidence: Evidence,
) -> Unseen:
    """``world`` at the robot's first look, once its branches fit the memory budget; under
    ``auto``, more than :data:`~brain.model.size.EXACT_MAX_BRANCHES` joint branches, or ones
    that do not fit, give way to the factored world (not yet looked).

    Raises:
        ModelTooLarge: ``joint`` branches that do not fit; a factored world that cannot.
    """
    if not isinstance(world, JointWorld):
        return world
    auto = settings.unseen_world is UnseenWorld.AUTO
    try:
        if auto and len(world.view.rows) > EXACT_MAX_BRANCHES:
            raise ModelTooLarge(f"{len(world.view.rows)} joint branches")
        check_tracking_size(scene, settings, len(world.view.rows), person_model)
    except ModelTooLarge:
        if not auto:
            raise
        return factored_world(scene, settings, person_model, people, evidence)
    return world


def believed_state(state: State, model: WorldModel, believed: IntArray) -> State:
    """``state`` with every item resting out of the robot's sight where ``believed`` ``(K,)``
    puts it (location indices, the likeliest world's: what the robot acts on); a carried
    item, and one the model does not know, as they are."""
    items = tuple(
        item
        if item.held_by is not None or item.id not in model.items
        else msgspec.structs.replace(
            item, location=model.locations[max(int(believed[model.items.index(item.id)]), 0)]
        )
        for item in state.items
    )
    return msgspec.structs.replace(state, items=items)
