"""Issue 49: random scenario and map files, within the stated limits and beyond them
(:mod:`protocol.limits`), and with numbers that are NaN, infinite, fractional where an
integer is due or of the wrong type. Each is either accepted and runs (the engine builds the
world, its scene passes the handshake's check, it steps a few ticks) or refused by the loader
in one line (:class:`~sim2d.errors.ScenarioError`), within a CPU-time and a memory bound: nothing
else (no traceback of another kind, no hang, no gigabytes)."""

from __future__ import annotations

import resource
import time
from pathlib import Path
from typing import Any

from hypothesis import HealthCheck, event, given, settings
from hypothesis import strategies as st

from protocol import scene_problems
from sim2d.engine import Engine
from sim2d.errors import ScenarioError
from sim2d.scenario.scenario import load_scenario

SECONDS = 30.0
"""The most one file may take to be refused, or loaded, built and stepped (an accepted grid
here is at most 60 x 60 cells: about 0.1 s; generous for a loaded 2-core machine)."""
MAX_RSS_MB = 1500
"""The process may never grow past this (a refused 10^10-cell grid must not be built)."""

ODD = st.sampled_from(["nan", "inf", "-inf", "-1", "0", "2.5", '"3"', "true", "[1]", "1e400"])
"""Values that are wrong for some number field (TOML's ``1e400`` is ``inf``)."""


def _value(draw: Any, good: str) -> str:
    """Mostly ``good`` (nine times in ten), else an odd value."""
    return draw(ODD) if draw(st.integers(0, 9)) == 0 else good


@st.composite
def files(draw: Any) -> tuple[str, str]:
    """``(map TOML, scenario TOML)``: one room (and an outside) of a drawn size, spots,
    items and people; sizes mostly small, sometimes beyond the limits."""
    small = st.integers(1, 60)
    huge = st.sampled_from([201, 1000, 99_995, 100_000, 10**9])
    columns = draw(huge) if draw(st.integers(0, 7)) == 0 else draw(small)
    rows = draw(huge) if draw(st.integers(0, 7)) == 0 else draw(small)
    width, height = max(columns, 1), max(rows - 2, 1)
    spots = draw(st.integers(1, min(width * height, 250) if width * height > 1 else 1))
    n_items = (
        draw(st.sampled_from([100, 101, 1000])) if draw(st.integers(0, 7)) == 0 else draw(st.integers(0, 12))
    )
    n_people = draw(st.sampled_from([100, 101])) if draw(st.integers(0, 7)) == 0 else draw(st.integers(1, 8))
    cells = [(c, 2 + r) for r in range(min(height, 500)) for c in range(min(width, 500))]
    game_map = [
        'name = "random"',
        f"cell_size = {_value(draw, draw(st.sampled_from(['1.0', '0.5', '2'])))}",
        f"columns = {_value(draw, str(columns))}",
        f"rows = {_value(draw, str(rows))}",
        f'[[regions]]\nid = "R"\nkind = "playground"\nrects = [[0, 2, {width}, {height}]]',
        f'[[regions]]\nid = "O"\nkind = "outside"\nrects = [[0, 0, {width}, 1]]',
        '[[doors]]\nid = "d"\ncell = [0, 1]\njoins = ["R", "O"]',
    ]
    for i, (c, r) in enumerate(cells[:spots]):
        game_map.append(
            f'[[locations]]\nid = "s{i}"\nregion = "R"\ncell = [{c}, {r}]\nplay = {str(i == 0).lower()}'
        )
    scenario = [
        'name = "random"\nmap = "random.map.toml"',
        f"tick_seconds = {_value(draw, '0.1')}",
        f"max_ticks = {_value(draw, '50')}",
        f"settle_ticks = {_value(draw, '1')}",
    ]
    scenario += [f'[[items]]\nid = "i{k}"\nat = "s{k % spots}"' for k in range(n_items)]
    for p in range(n_people):
        c, r = cells[p % len(cells)]
        script = '[{ do = "goto", location = "s0" }]'
        scenario.append(f'[[agents]]\nid = "p{p}"\nhome = [{c}, {r}]\nscript = {script}')
    return "\n".join(game_map) + "\n", "\n\n".join(scenario) + "\n"


def _runs(path: Path) -> str:
    """``accepted`` once the scenario loads, builds, passes the scene check and steps, or
    ``refused`` with a one-line loader error; anything else fails the test."""
    try:
        scenario = load_scenario(str(path))
    except ScenarioError as err:
        message = str(err)
        assert message.startswith(str(path.parent)) and "\n" not in message, (
            f"expected one line naming the file, got {message!r}"
        )
        return "refused"
    engine = Engine(scenario)
    problems = scene_problems(engine.scene())
    assert problems == [], f"an accepted scenario's scene should pass the handshake's check, got {problems}"
    for _ in range(3):
        engine.step()
    return "accepted"


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(files())
def test_random_files_are_run_or_refused_in_one_line(tmp_path_factory: Any, drawn: tuple[str, str]) -> None:
    folder: Path = tmp_path_factory.mktemp("random")
    (folder / "random.map.toml").write_text(drawn[0])
    (folder / "random.toml").write_text(drawn[1])
    start = time.process_time()  # CPU time: a loaded machine's waits do not count against the file
    outcome = _runs(folder / "random.toml")
    event(outcome)
    took = time.process_time() - start
    rss_mb = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024
    assert took < SECONDS, f"expected the file {outcome} within {SECONDS} CPU s, took {took:.1f} s"
    assert rss_mb < MAX_RSS_MB, f"expected the process under {MAX_RSS_MB} MB, it reached {rss_mb:.0f} MB"
