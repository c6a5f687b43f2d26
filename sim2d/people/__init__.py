"""Simulated people (:class:`.person.Person`): scripted ones who follow their route
(:mod:`.scripted`), autonomous ones with a true belief (:mod:`.belief`) and habits of their
own (:mod:`.autonomous`, a task episode's first jobs: :mod:`.firstjobs`), and planned ones
who act by the brain's planner (:mod:`.planned`, its table: :mod:`.policytable`); what an
autonomous person is doing (:mod:`.pursuit`), and what they tell each other (:mod:`.hearsay`)."""

from .autonomous import AutonomousPerson
from .belief import PersonBelief
from .firstjobs import FirstJobs
from .hearsay import exchange, tell_jobs
from .person import Person
from .planned import PlannedPerson
from .policytable import PolicyTable, PolicyTableError, load_policy_table
from .pursuit import Primitive, Reconsider, pointless, pursuit_of
from .scripted import ScriptedPerson

__all__ = [
    "exchange",
    "load_policy_table",
    "pointless",
    "pursuit_of",
    "tell_jobs",
    "AutonomousPerson",
    "FirstJobs",
    "Person",
    "PersonBelief",
    "PlannedPerson",
    "PolicyTable",
    "PolicyTableError",
    "Primitive",
    "Reconsider",
    "ScriptedPerson",
]
