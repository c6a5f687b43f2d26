"""The forms of one person's hidden-state model, behind one interface for the tracker
(:mod:`brain.model.person.personinterface`), and :func:`person_model`, which picks one.

- :class:`~brain.model.person.exactperson.ExactModel`: the joint ``(W, U)`` posterior over believed
  worlds and candidate desires (the paper's point-belief model; online and smoothed).
- :class:`~brain.model.person.factoredperson.FactoredModel`: per preference, one belief per item
  (:mod:`brain.model.factored`), for houses whose ``W = V**K`` worlds do not fit; online only.
- :class:`~brain.model.person.gradedperson.GradedModel`: each person holds a graded belief of their
  own and plans with it (:mod:`brain.model.graded`); ``ModelSettings.belief_model =
  "graded"``; online and smoothed.
- :class:`~brain.model.person.gradedfactored.GradedFactoredModel`: graded beliefs in the factored form.

:func:`person_model` picks one by ``belief_model`` (graded by default) and
``exact_max_worlds``, wrapped in :class:`~brain.model.person.lapses.LapseModel` for lapses and hearsay.
"""

from __future__ import annotations

import logging

from protocol import Scene

from ...settings import ModelSettings
from ..size import check_model_size
from ..world import build_world_model
from .exactperson import ExactModel
from .factoredperson import FactoredModel
from .gradedfactored import GradedFactoredModel
from .gradedperson import GradedModel
from .lapses import LapseModel
from .personinterface import PersonModel

log = logging.getLogger(__name__)


def person_model(scene: Scene, settings: ModelSettings, *, true_world: bool = False) -> PersonModel:
    """:func:`base_person_model`, wrapped to allow lapses of attention and hearsay when
    ``settings.miss`` or ``settings.hearsay_per_s`` is above 0 (:mod:`brain.model.person.lapses`)."""
    base = base_person_model(scene, settings, true_world=true_world)
    lapses = settings.miss > 0 or settings.hearsay_per_s > 0
    return LapseModel(base, settings.miss) if lapses and not true_world else base


def base_person_model(scene: Scene, settings: ModelSettings, *, true_world: bool = False) -> PersonModel:
    """The model ``settings.belief_model`` names, graded (the default) or point: exact while
    the scene's ``W`` worlds are at most ``settings.exact_max_worlds``, factored above it
    (:mod:`brain.model.person.gradedfactored`, :mod:`brain.model.factored`).

    Raises:
        ModelTooLarge: its arrays would exceed :data:`brain.model.size.MAX_MODEL_BYTES`.
    """
    check_model_size(scene, settings)  # before anything of its size is allocated
    worlds = build_world_model(scene).n_worlds
    if worlds > settings.exact_max_worlds:
        if settings.desire_model == "graded" or settings.person_planner == "belief":
            log.warning(
                "scene '%s' has %d worlds (exact_max_worlds = %d): the factored model has "
                "favourite desires and QMDP only (desire_model and person_planner ignored)",
                scene.name,
                worlds,
                settings.exact_max_worlds,
            )
        if settings.belief_model == "graded":
            return GradedFactoredModel(scene, settings, true_world)
        return FactoredModel(scene, settings, true_world)
    if settings.belief_model == "graded":
        return GradedModel(scene, settings, true_world)
    return ExactModel(scene, settings, true_world)
