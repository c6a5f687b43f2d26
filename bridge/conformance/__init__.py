"""The engine conformance kit: :func:`check_engine` runs every check of :data:`CHECKS` (the
registry of free ``check_<name>(probe)`` functions) against the engine serving a world
(``toyroom conform``), each ending with a :class:`CheckOutcome` (passed, skipped with a
reason, not applicable, failed); :mod:`.suite` has the same checks as a pytest mixin (it
needs pytest, so it is not imported here)."""

from .checks import CHECK_NAMES, CHECKS, Check, check_engine, run_check, run_checks, summary
from .probe import CheckFailed, CheckOutcome, CheckResult, CheckSkipped, NotApplicable, Probe

__all__ = [
    "CHECKS",
    "CHECK_NAMES",
    "Check",
    "CheckFailed",
    "CheckOutcome",
    "CheckResult",
    "CheckSkipped",
    "NotApplicable",
    "Probe",
    "check_engine",
    "run_check",
    "run_checks",
    "summary",
]
