"""The package direction is the architecture: protocol <- bridge <- sim2d, brain <- toyroom.

``brain`` and ``sim2d`` meet only on the wire; the application (``toyroom``) starts them as
processes; of ``brain`` only its fitting room imports it (it replays the model in-process),
and of both only its bench room (it times the engine's tick and the brain's update
in-process); ``bridge`` imports neither; no library imports the application;
``protocol`` depends on no other package of ours. Also: lint and types.
"""

from __future__ import annotations

import ast
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
ALLOWED = {
    "protocol": set(),
    "bridge": {"protocol"},
    "sim2d": {"protocol", "bridge"},
    "brain": {"protocol", "bridge"},
    "toyroom": {"protocol", "bridge", "brain", "sim2d"},
}


def _imports(path: Path) -> set[str]:
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    found: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found.update(alias.name.split(".")[0] for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            found.add(node.module.split(".")[0])
    return found


@pytest.mark.parametrize("package", sorted(ALLOWED))
def test_package_imports_only_what_it_may(package: str) -> None:
    forbidden = set(ALLOWED) - ALLOWED[package] - {package}
    offenders = {
        str(path.relative_to(ROOT)): sorted(_imports(path) & forbidden)
        for path in (ROOT / package).rglob("*.py")
        if _imports(path) & forbidden
    }
    assert offenders == {}, f"{package} may import only {sorted(ALLOWED[package])}; found {offenders}"


def _run(*command: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run(command, cwd=ROOT, capture_output=True, text=True, timeout=300)


def test_ruff_is_clean() -> None:
    result = _run(sys.executable, "-m", "ruff", "check", ".")
    assert result.returncode == 0, result.stdout + result.stderr


def test_mypy_is_clean() -> None:
    result = _run(sys.executable, "-m", "mypy")
    assert result.returncode == 0, result.stdout + result.stderr


def _modules(path: Path) -> set[str]:
    """The full names of the modules ``path`` imports from (absolute imports only)."""
    tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
    found: set[str] = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            found.add(node.module)
    return found


def test_nodes_do_not_import_the_command_line() -> None:
    """The nodes take their shared flags from the bridge core (``bridge.flags``,
    ``bridge.session``), never from the ``toyroom`` application."""
    offenders = sorted(
        str(path.relative_to(ROOT))
        for package in ("sim2d", "brain")
        for path in (ROOT / package).rglob("*.py")
        if any(m == "toyroom.cli" or m.startswith("toyroom.cli.") for m in _modules(path))
    )
    assert offenders == [], f"nodes importing toyroom.cli: {offenders}"


ROOMS = {
    "bridge": {
        "<core>": set(),
        "recording": {"<core>"},
        "conformance": {"<core>"},
    },
    "toyroom": {
        "<core>": set(),
        "view": set(),
        "evaluation": set(),
        "fitting": {"evaluation", "play"},
        "rating": {"view", "play"},  # play: which recordings are incomplete (their metadata)
        "play": {"view"},  # view: the people's colours, one per person on every page
        "cli": {"evaluation", "fitting", "gateway"},
        "bench": {"evaluation", "gateway"},
        "gateway": set(),
    },
    "brain": {
        "<base>": set(),
        "model": {"<base>"},
        "memory": {"<base>", "model"},
        "tracking": {"<base>", "model", "memory"},
        "robot": {"<base>", "model", "tracking"},
        "outputs": {"<base>", "model", "tracking"},
        "<shell>": {"<base>", "model", "memory", "tracking", "robot", "outputs"},
    },
}
"""Inside a package, the rooms each room may import: the bridge core imports none of its
tools; the brain's model is pure (settings and errors are its base), the node its only shell."""

ENTRY_POINTS = {"toyroom/__main__.py"}
"""Modules that only start a tool (``python -m toyroom`` runs the CLI)."""
BRAIN_BASE = {"settings", "robotsettings", "errors"}


def _room(package: str, path: Path) -> str:
    rel = path.relative_to(ROOT / package)
    if len(rel.parts) > 1:
        return rel.parts[0]
    if package == "brain":
        return "<base>" if rel.stem in BRAIN_BASE else "<shell>"
    return "<core>"


def _room_of_module(package: str, module: str) -> str:
    parts = module.split(".")[1:]
    if parts and (ROOT / package / parts[0]).is_dir():
        return parts[0]
    if package == "brain":
        return "<base>" if parts and parts[0] in BRAIN_BASE else "<shell>"
    return "<core>"


def _absolute_imports(path: Path) -> set[str]:
    """Every module ``path`` imports, relative imports resolved, lazy ones included."""
    package = list(path.relative_to(ROOT).with_suffix("").parts)
    package = package[:-1]
    found: set[str] = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            found.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level == 0:
                found.add(node.module or "")
            else:
                base = package[: len(package) - (node.level - 1)]
                found.add(".".join(base + ([node.module] if node.module else [])))
    return found


@pytest.mark.parametrize("package", sorted(ROOMS))
def test_rooms_import_only_what_they_may(package: str) -> None:
    offenders = []
    for path in sorted((ROOT / package).rglob("*.py")):
        if str(path.relative_to(ROOT)) in ENTRY_POINTS:
            continue
        room = _room(package, path)
        for module in _absolute_imports(path):
            if module.split(".")[0] != package:
                continue
            target = _room_of_module(package, module)
            if target != room and target not in ROOMS[package][room]:
                offenders.append(f"{path.relative_to(ROOT)} ({room}) imports {module} ({target})")
    assert offenders == [], f"{package}: rooms importing what they may not: {offenders}"


def test_the_brain_model_is_pure() -> None:
    """brain/model imports no bridge, no zenoh, nothing that does I/O on the wire."""
    offenders = {
        str(path.relative_to(ROOT)): sorted(
            m for m in _absolute_imports(path) if m.split(".")[0] in {"bridge", "zenoh"}
        )
        for path in (ROOT / "brain" / "model").rglob("*.py")
    }
    assert {k: v for k, v in offenders.items() if v} == {}, offenders


MAX_FUNCTION_LINES = 80
MAX_TOP_MODULES = 12


def test_every_module_says_what_its_concept_is() -> None:
    """A module is one concept, whatever its length (issue 68 dropped the 400-line cap, which
    split modules by size): its docstring names the concept. ``ruff``'s ``D`` rules hold the
    same for the public API (pyproject.toml); this check needs no configuration to hold."""
    bare = [
        str(path.relative_to(ROOT))
        for package in ALLOWED
        for path in sorted((ROOT / package).rglob("*.py"))
        if not (ast.get_docstring(ast.parse(path.read_text(encoding="utf-8"))) or "").strip()
    ]
    assert bare == [], f"modules without a docstring saying what their concept is: {bare}"


def test_functions_are_short() -> None:
    long = []
    for package in ALLOWED:
        for path in sorted((ROOT / package).rglob("*.py")):
            rel = path.relative_to(ROOT)
            for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
                if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
                    length = (node.end_lineno or node.lineno) - node.lineno + 1
                    if length > MAX_FUNCTION_LINES:
                        long.append(
                            f"{rel}:{node.lineno} {node.name}: {length} lines (at most {MAX_FUNCTION_LINES})"
                        )
    assert long == [], "too long:\n" + "\n".join(long)


@pytest.mark.parametrize("package", ["bridge", "brain"])
def test_top_level_has_few_modules(package: str) -> None:
    modules = sorted(p.name for p in (ROOT / package).glob("*.py"))
    assert len(modules) <= MAX_TOP_MODULES, f"{package}/ has {len(modules)} modules at its top: {modules}"


BRIDGE_BUDGET = 5_000
"""The most lines ``bridge/`` may hold, every line of its modules counted (``wc -l``): the wire
is a library an engine's author reads whole. It was 5,248 at d227688 (issue 68), the WebSocket
gateway inside it; the gateway, a node built on the wire as the engine and the brain are, is
``toyroom.gateway`` now."""


def test_the_bridge_stays_within_its_budget() -> None:
    lines = {
        str(path.relative_to(ROOT)): len(path.read_text(encoding="utf-8").splitlines())
        for path in sorted((ROOT / "bridge").rglob("*.py"))
    }
    total = sum(lines.values())
    largest = ", ".join(f"{name} {n}" for name, n in sorted(lines.items(), key=lambda kv: -kv[1])[:5])
    assert total <= BRIDGE_BUDGET, (
        f"bridge/ holds {total:,} lines, over its budget of {BRIDGE_BUDGET:,}: move what is not the "
        f"wire to the application (toyroom/), or re-state the budget here with the reason; "
        f"largest: {largest}"
    )


def _exported(init: Path) -> list[str]:
    """The names in an ``__init__``'s ``__all__`` (empty when it has none)."""
    for node in ast.parse(init.read_text(encoding="utf-8")).body:
        targets = node.targets if isinstance(node, ast.Assign) else []
        if any(isinstance(t, ast.Name) and t.id == "__all__" for t in targets):
            assert isinstance(node, ast.Assign) and isinstance(node.value, ast.List | ast.Tuple)
            return [ast.literal_eval(e) for e in node.value.elts]
    return []


def test_every_package_exports_its_public_names() -> None:
    empty = [
        str(init.relative_to(ROOT))
        for package in ALLOWED
        for init in sorted((ROOT / package).rglob("__init__.py"))
        if not _exported(init)
    ]
    assert empty == [], f"package __init__ files without a non-empty __all__: {empty}"


LIBRARY_ROOMS = {"fitting": {"brain"}, "bench": {"brain", "sim2d"}}
"""The application's rooms that import the libraries it otherwise runs as processes."""


def test_only_the_fitting_and_bench_rooms_of_the_application_import_the_libraries() -> None:
    """``toyroom`` runs the brain and the engine as processes; ``toyroom.fitting`` alone
    replays the brain's model in-process (a fit scores thousands of parameter points), and
    ``toyroom.bench`` alone times the engine's tick and the brain's update in-process (a
    process boundary would be timed with them)."""
    offenders = sorted(
        f"{path.relative_to(ROOT)} imports {module}"
        for path in (ROOT / "toyroom").rglob("*.py")
        for module in _absolute_imports(path)
        if module.split(".")[0] in {"brain", "sim2d"}
        and module.split(".")[0] not in LIBRARY_ROOMS.get(path.relative_to(ROOT / "toyroom").parts[0], set())
    )
    assert offenders == [], f"toyroom importing brain or sim2d outside {LIBRARY_ROOMS}: {offenders}"


def test_the_robot_mode_is_written_only_in_its_enum() -> None:
    """``act`` and ``observe`` are :class:`protocol.RobotMode`'s: no other module of the
    packages writes either as a string (a scenario's ``robot``, every ``--robot``)."""
    from protocol import RobotMode

    home = ROOT / "protocol" / "choices.py"
    written = []
    for package in ALLOWED:
        for path in sorted((ROOT / package).rglob("*.py")):
            if path == home:
                continue
            for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
                if isinstance(node, ast.Constant) and node.value in RobotMode.names():
                    written.append(f"{path.relative_to(ROOT)}:{node.lineno} {node.value!r}")
    assert written == [], "use protocol.RobotMode:\n" + "\n".join(written)


def test_sim2d_writes_no_item_value_arithmetic() -> None:
    """The item-value encoding (``v = 2 l + held``) is :mod:`protocol.itemvalue`'s: sim2d reads
    the brain's policy table with its functions, never with ``2 *`` or ``::2`` by hand."""
    arithmetic = re.compile(r"\b2 \* |::\s*2\s*\]")
    written = [
        f"{path.relative_to(ROOT)}:{number}: {line.strip()}"
        for path in sorted((ROOT / "sim2d").rglob("*.py"))
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1)
        if arithmetic.search(line)
    ]
    assert written == [], "use protocol.itemvalue:\n" + "\n".join(written)


NAMED_TWICE: set[str] = set()
"""Class names still defined in two modules of the packages, to be renamed (issue 68); the
list only shrinks (empty: every class name means one thing)."""


def test_a_class_name_means_one_thing() -> None:
    """No two classes of the packages share a name (``brain.model.planner.PlanPolicy`` is
    not :class:`protocol.Policy`), but the ones :data:`NAMED_TWICE` still lists."""
    homes: dict[str, list[str]] = {}
    for package in ALLOWED:
        for path in sorted((ROOT / package).rglob("*.py")):
            for node in ast.parse(path.read_text(encoding="utf-8")).body:
                if isinstance(node, ast.ClassDef):
                    homes.setdefault(node.name, []).append(str(path.relative_to(ROOT)))
    twice = {name: where for name, where in homes.items() if len(where) > 1}
    new = {name: where for name, where in twice.items() if name not in NAMED_TWICE}
    assert new == {}, f"class names defined more than once: {new}"
    gone = sorted(NAMED_TWICE - set(twice))
    assert gone == [], f"renamed already: take {gone} off NAMED_TWICE"


def test_metric_names_are_listed_only_in_the_metrics_record() -> None:
    """The metrics are :class:`toyroom.evaluation.scores.Scores`'s fields: no other module of
    the packages writes a list (a tuple, list or set of two or more) of metric names by hand;
    the report's tables, the intervals and the tests take them from the record
    (:func:`~toyroom.evaluation.scores.metric_names`)."""
    from toyroom.evaluation.scores import metric_names

    names = set(metric_names())
    home = ROOT / "toyroom" / "evaluation" / "scores.py"
    written = []
    for package in ALLOWED:
        for path in sorted((ROOT / package).rglob("*.py")):
            if path == home:
                continue
            for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
                if isinstance(node, (ast.Tuple, ast.List, ast.Set)):
                    listed = [e.value for e in node.elts if isinstance(e, ast.Constant) and e.value in names]
                    if len(listed) >= 2:
                        written.append(f"{path.relative_to(ROOT)}:{node.lineno} {listed}")
    assert written == [], "use toyroom.evaluation.scores.metric_names:\n" + "\n".join(written)
