"""The conformance kit as a reusable pytest suite, in the manner of dm_env's test mixins.

Inherit :class:`EngineConformance` in a test class and give it a class-scoped fixture
``conformance_world`` that starts an engine and yields its world name; every check then
runs as its own test. A check that is skipped (with its reason) or does not apply to the
engine is a skipped test; set ``strict = True`` on the class to fail on a skip instead::

    class TestMyEngine(EngineConformance):
        @pytest.fixture(scope="class")
        @classmethod
        def conformance_world(cls):
            with start_my_engine("my-world"):
                yield "my-world"

Needs pytest (the ``test`` extra); the rest of ``bridge`` does not.
"""

from __future__ import annotations

from collections.abc import Iterator

import pytest

from ..bridge import Bridge
from .checks import CHECK_NAMES, CheckResult, check_engine
from .probe import CheckOutcome


class EngineConformance:
    """Every conformance check as a test; subclasses provide ``conformance_world``."""

    timeout: float = 10.0
    strict: bool = False
    """Fail on a skipped check (one that applies but found nothing to exercise)."""

    @pytest.fixture(scope="class")
    @classmethod
    def conformance_results(cls, conformance_world: str) -> Iterator[dict[str, CheckResult]]:
        with Bridge(conformance_world) as bridge:
            yield {result.name: result for result in check_engine(bridge, cls.timeout)}

    def _passed(self, results: dict[str, CheckResult], name: str) -> None:
        assert name in results, f"check '{name}' did not run (an earlier check failed): {list(results)}"
        result = results[name]
        skip = result.outcome is CheckOutcome.SKIPPED and not self.strict
        if skip or result.outcome is CheckOutcome.NOT_APPLICABLE:
            pytest.skip(result.line())
        assert result.passed, result.line()

    @pytest.mark.parametrize("check", CHECK_NAMES)
    def test_check(self, conformance_results: dict[str, CheckResult], check: str) -> None:
        self._passed(conformance_results, check)
