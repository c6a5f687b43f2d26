"""The stored Q-values' file names (``brain/outputs/valuestore.py``) follow the source of every
module the planner's solution runs through, so a changed solver never reads old values."""

from __future__ import annotations

import ast
import importlib
from pathlib import Path

import pytest

from brain.model import goalvalues, planner
from brain.outputs import valuestore
from sim2d.engine import Engine


def _model_imports(module: object) -> set[str]:
    """The ``brain.model`` modules ``module`` imports, directly or through them."""
    seen: set[str] = set()
    todo = [module]
    while todo:
        source = Path(todo.pop().__file__).read_text(encoding="utf-8")  # type: ignore[attr-defined]
        for node in ast.walk(ast.parse(source)):
            if isinstance(node, ast.ImportFrom) and node.level == 1 and node.module:
                name = f"brain.model.{node.module}"
                if name not in seen:
                    seen.add(name)
                    todo.append(importlib.import_module(name))
    return seen


def test_every_module_of_the_solution_names_the_stored_values() -> None:
    kept = {m.__name__ for m in valuestore.SOURCES}
    needed = _model_imports(planner) | {planner.__name__}
    assert goalvalues.__name__ in needed, "the planner solves every candidate with goalvalues.solve_goals"
    assert needed <= kept, f"modules the planner runs through but the store's digest ignores: {needed - kept}"


def test_a_changed_goal_solver_renames_the_stored_values(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    scene = Engine("paper-1").scene()
    store = valuestore.ValueDirectory(tmp_path / "values")
    key = ("some", "settings")
    valuestore._sources.cache_clear()
    before = store.path(scene, key)
    changed = tmp_path / "goalvalues.py"
    changed.write_text(
        Path(goalvalues.__file__).read_text(encoding="utf-8") + "\n# changed\n", encoding="utf-8"
    )
    monkeypatch.setattr(goalvalues, "__file__", str(changed))
    valuestore._sources.cache_clear()
    try:
        after = store.path(scene, key)
    finally:
        monkeypatch.undo()
        valuestore._sources.cache_clear()
    assert after != before, "a change to goalvalues.py should name the stored values anew"
    assert store.path(scene, key) == before
