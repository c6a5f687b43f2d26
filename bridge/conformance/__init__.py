"""The engine conformance kit: :func:`check_engine` runs every check of :data:`CHECK_NAMES`
against the engine serving a world (``toyroom conform``), each ending with an
:class:`Outcome` (passed, skipped with a reason, not applicable, failed); :mod:`.suite` has
the same checks as a pytest mixin (it needs pytest, so it is not imported here)."""

from .checks import CHECK_NAMES, Checker, check_engine, summary
from .probe import CheckFailed, CheckResult, CheckSkipped, NotApplicable, Outcome, Probe

__all__ = [
    "CHECK_NAMES",
    "CheckFailed",
    "CheckResult",
    "CheckSkipped",
    "Checker",
    "NotApplicable",
    "Outcome",
    "Probe",
    "check_engine",
    "summary",
]
