"""The engine conformance kit: :func:`check_engine` runs every check of :data:`CHECK_NAMES`
against the engine serving a world (``toyroom conform``); :mod:`.suite` has the same checks as
a pytest mixin (it needs pytest, so it is not imported here)."""

from .checks import CHECK_NAMES, Checker, check_engine
from .probe import CheckFailed, CheckResult, Probe

__all__ = ["CHECK_NAMES", "CheckFailed", "CheckResult", "Checker", "Probe", "check_engine"]
