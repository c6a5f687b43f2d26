"""The test tiers. ``make check`` runs the fast tier: every test that starts no process, Zenoh
session, browser or Ray (``pytest --tier check``); ``make test`` runs every test but the
sweeps; ``make sweeps`` runs the sweeps (``pytest --tier sweeps``): the tests marked
``sweep``, each a benchmark or a study run end to end over minutes of CPU (``toyroom bench
--quick``, a parameter's recovery over a dozen episodes). CI runs both. The fast tier also
runs the tests marked ``example``: each runs one of ``examples/`` as real processes, in seconds.

A test is marked ``process`` when its own code, a fixture it uses or a helper it calls (in
its module, its class or ``support``) names one of :data:`STARTERS`; a test may also carry
the mark by hand (``@pytest.mark.process`` or a module's ``pytestmark``). In the fast tier a
guard makes an unmarked test that starts something anyway fail, saying so and naming what
it started, so a missing mark is found at once instead of silently slowing the tier.
"""

from __future__ import annotations

import ast
import inspect
import multiprocessing.process
import os
import subprocess
import sys
import textwrap
from collections.abc import Callable, Iterator
from types import FunctionType, ModuleType
from typing import Any

import pytest

MARK = "process"
SWEEP = "sweep"
EXAMPLE = "example"
"""A test that runs one of ``examples/`` as real processes, in seconds: the fast tier keeps it
(the examples run in ``make check``, as zenoh-python's CI runs its examples)."""
STARTERS = frozenset(
    {
        # processes
        "subprocess",
        "Popen",
        "multiprocessing",
        "ProcessPoolExecutor",
        "fork",
        "EngineProcess",
        "BrainProcess",
        "GatewayProcess",
        "run_brain",
        "toyroom_run",
        "toyroom_fit",
        "toyroom",
        # Zenoh sessions
        "zenoh",
        "Bridge",
        "bridges",
        "Router",
        # the project's and the tests' own starters
        "Gateway",
        "run_episode",
        "run_episodes",
        "evaluate",
        "run_doctor",
        "run_and_read",
        "study",
        "bench",
        "run_batch",
        "generate_all",
        "eval_main",
        "RunProcess",
        # browsers and Ray
        "Browser",
        "chromium",
        "ray",
    }
)
"""Names whose use means a test starts a process, a Zenoh session, a browser or Ray."""


def pytest_addoption(parser: pytest.Parser) -> None:
    parser.addoption(
        "--tier",
        choices=("check", "test", "sweeps"),
        default="test",
        help="check: only the tests that start no process, Zenoh session, browser or Ray; "
        "test: all but the sweeps; sweeps: only the benchmarks and studies run end to end",
    )


def pytest_configure(config: pytest.Config) -> None:
    config.addinivalue_line(
        "markers", f"{MARK}: starts a process, a Zenoh session, a browser or Ray (not in `make check`)"
    )
    config.addinivalue_line(
        "markers", f"{SWEEP}: a benchmark or study run end to end (only in `make sweeps`, which CI runs)"
    )
    config.addinivalue_line(
        "markers", f"{EXAMPLE}: runs an example of examples/ as processes, in seconds (in `make check` too)"
    )


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    starts = _Scanner()
    for item in items:
        if item.get_closest_marker(MARK) is None and starts.item(item):
            item.add_marker(MARK)
    tier = config.getoption("--tier")
    if tier == "sweeps":
        kept = [item for item in items if item.get_closest_marker(SWEEP) is not None]
    elif tier == "test":
        kept = [item for item in items if item.get_closest_marker(SWEEP) is None]
    else:
        kept = [
            item
            for item in items
            if item.get_closest_marker(SWEEP) is None
            and (item.get_closest_marker(MARK) is None or item.get_closest_marker(EXAMPLE) is not None)
        ]
    config.hook.pytest_deselected(items=[item for item in items if item not in kept])
    items[:] = kept


@pytest.fixture(autouse=True)
def _tier_guard(request: pytest.FixtureRequest) -> Iterator[None]:
    """In the fast tier, fail a test that starts a process or a Zenoh session unmarked."""
    if request.config.getoption("--tier") != "check" or request.node.get_closest_marker(EXAMPLE):
        yield
        return
    with pytest.MonkeyPatch.context() as patch:
        for owner, name in _guarded():
            patch.setattr(owner, name, _refuse(request.node.nodeid, f"{_label(owner)}.{name}"))
        yield


def _guarded() -> list[tuple[Any, str]]:
    found: list[tuple[Any, str]] = [
        (subprocess.Popen, "__init__"),
        (os, "fork"),
        (multiprocessing.process.BaseProcess, "start"),
    ]
    for module, name in (("zenoh", "open"), ("ray", "init")):
        if module in sys.modules:
            found.append((sys.modules[module], name))
    return found


def _label(owner: Any) -> str:
    return getattr(owner, "__name__", type(owner).__name__)


def _refuse(test: str, what: str) -> Callable[..., Any]:
    def refuse(*args: object, **kwargs: object) -> Any:
        pytest.fail(
            f"{test} called {what} in the fast tier: mark it @pytest.mark.{MARK} "
            f"(or name what starts it in tests/tiers.py STARTERS)",
            pytrace=False,
        )

    return refuse


class _Scanner:
    """Whether a test's code reaches one of :data:`STARTERS` (memoised per function)."""

    def __init__(self) -> None:
        self._seen: dict[object, bool] = {}

    def item(self, item: pytest.Item) -> bool:
        if not isinstance(item, pytest.Function):
            return False
        module = item.module
        if item.cls is not None and self._code(item.cls, module):
            return True
        if self._code(item.function, module):
            return True
        info = getattr(item, "_fixtureinfo", None)
        definitions = info.name2fixturedefs.values() if info is not None else ()
        for defs in definitions:
            for definition in defs:
                if definition.argname in STARTERS:
                    return True
                func = definition.func
                if func.__module__ == __name__:
                    continue  # the guard itself
                if self._code(func, sys.modules.get(func.__module__)):
                    return True
        return False

    def _code(self, obj: object, module: ModuleType | None) -> bool:
        key = id(obj)
        if key in self._seen:
            return self._seen[key]
        self._seen[key] = False  # a recursive helper ends here
        result = self._scan(obj, module)
        self._seen[key] = result
        return result

    def _scan(self, obj: object, module: ModuleType | None) -> bool:
        try:
            tree = ast.parse(textwrap.dedent(inspect.getsource(obj)))  # type: ignore[arg-type]
        except (OSError, TypeError, SyntaxError):
            return False
        names = _names(tree)
        if names & STARTERS:
            return True
        scope = vars(module) if module is not None else {}
        for name in names:
            helper = scope.get(name)
            if _local(helper) and self._code(helper, sys.modules.get(helper.__module__)):
                return True
        return False


def _names(tree: ast.AST) -> set[str]:
    found: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Name):
            found.add(node.id)
        elif isinstance(node, ast.Attribute):
            found.add(node.attr)
        elif isinstance(node, ast.arg):
            found.add(node.arg)  # fixtures named as parameters
        elif isinstance(node, ast.alias):
            found.add(node.asname or node.name.split(".")[0])
    return found


def _local(obj: object) -> bool:
    """A function or class of the tests themselves (not of the project or a library)."""
    if not isinstance(obj, (FunctionType, type)):
        return False
    file = getattr(sys.modules.get(obj.__module__), "__file__", None) or ""
    return f"{os.sep}tests{os.sep}" in file
