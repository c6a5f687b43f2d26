"""A person's filter, in each of its forms: what the tracker keeps of one person.

The interface (:mod:`.personinterface`: the record of an observed step, a person's online
filter and the model that makes filters and smooths a chain) and the forms that implement it,
on the model's math one floor down (:mod:`brain.model`): the exact point-belief model
(:mod:`.exactperson`), the factored one for large houses (:mod:`.factoredperson`), graded
beliefs (:mod:`.gradedperson`) and graded beliefs in the factored form
(:mod:`.gradedfactored`), lapses of attention around any of them (:mod:`.lapses`), what a
person remembered from an earlier day starts from (:mod:`.remembered`), and
:func:`~.personmodel.person_model`, which picks the form a scene's settings ask for."""

from .exactperson import ExactFilter, ExactModel
from .factoredperson import FactoredFilter, FactoredModel
from .gradedfactored import GradedFactoredFilter, GradedFactoredModel
from .gradedperson import GradedFilter, GradedModel
from .lapses import LapseFilter, LapseModel
from .personinterface import PersonFilter, PersonModel, StepRecord
from .personmodel import base_person_model, person_model
from .remembered import Remembered

__all__ = [
    "base_person_model",
    "person_model",
    "ExactFilter",
    "ExactModel",
    "FactoredFilter",
    "FactoredModel",
    "GradedFactoredFilter",
    "GradedFactoredModel",
    "GradedFilter",
    "GradedModel",
    "LapseFilter",
    "LapseModel",
    "PersonFilter",
    "PersonModel",
    "Remembered",
    "StepRecord",
]
