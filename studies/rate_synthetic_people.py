"""Synthetic ratings: does ``toyroom fit --judgments`` recover the settings people act by,
from ratings of what they believed and wanted, and do graded desires agree with those
ratings better than one favourite?

1. Episodes on the paper map (``paper-auto``) whose two people act by the brain's planner
   (``--minds model``: :mod:`sim2d.people.planned`) at the generating settings (``--beta``,
   ``--hazard``), in this process (no Zenoh), each written as a ``trace.jsonl``. People start
   sure of where an item is with chance ``--knows``, sure of a wrong place with ``--stale``,
   else not knowing. With ``--people graded`` (the default) each person wants every goal to
   a degree: the policy table's row for favourite goal ``d`` is replaced, per episode, by the
   Q-values of a utility vector of the graded grid (``desire_levels`` levels per goal) drawn
   among those whose one most wanted goal is ``d``, so the person's favourite (and its
   switches, at the hazard) picks a graded desire; ``--people favourite`` keeps the paper's
   one favourite.
2. Raters (``--raters``) watch each episode and answer, for each person, retrospective
   questions: where they believed each item was at the start (every item and location:
   ``belief``, of the smoothed estimate at the person's first step) and how much they wanted
   each goal (``utility``) at ``--desire-points`` evenly spaced ticks. Each rater's rating
   is a noisy monotone function of the GENERATING model's smoothed quantity ``x`` in
   ``[0, 1]`` (the brain at the generating settings, with the people's desire model):
   ``clip(round(1 + 6 (x ** g + N(0, noise))), 1, 7)``, with the rater's own curve
   ``g = exp(N(0, 0.3))``. Written as a rating page's CSV (``estimate = smoothed``, with
   ``participant`` and ``question`` columns).
3. ``toyroom fit RECORDINGS --judgments ratings.csv --models graded-desires,one-favourite
   --params beta`` (in this process): the likelihood fit and the fit to the ratings, each
   with its fitted ``beta`` against the generating one (recovered: within 25%), and each
   kind of judgment's held-out r, graded desires minus one favourite paired by episode.

    python studies/rate_synthetic_people.py [--episodes 24] [--ticks 1000] [--raters 8]
        [--people graded] [--grid 1,2,3,4,5,6,8,12] [--json FILE] [--out DIR]
"""

from __future__ import annotations

import argparse
import csv
import dataclasses
import json
import sys
import tempfile
import time
from collections.abc import Sequence
from pathlib import Path

import numpy as np

from brain.model.planner import solve
from brain.model.world import build_world_model
from brain.outputs.policytable import policy_table
from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from bridge.recording.trace import Trace, read_trace, trace_line
from protocol import ClockMode, Keys, Scene
from sim2d.engine import Engine
from sim2d.people import load_policy_table
from sim2d.scenario import Scenario, load_scenario
from toyroom.fitting.judged import estimate_at, goal_scale, utility

MODELS = ("graded-desires", "one-favourite")
"""The two desire models compared (``toyroom.fitting.search.MODELS``); the first is the reference."""
COLUMNS = ("episode", "tick", "person", "quantity", "target", "value", "estimate", "participant", "question")


@dataclasses.dataclass(frozen=True)
class Study:
    """What the study generates and how it is rated."""

    episodes: int = 24
    ticks: int = 1000
    beta: float = 4.0
    hazard: float = 0.02
    people: str = "graded"
    knows: float = 0.4
    stale: float = 0.3
    raters: int = 8
    noise: float = 0.1
    desire_points: int = 2
    read: str = "model"
    seed: int = 0

    @property
    def settings(self) -> ModelSettings:
        """The generating model: the brain at the settings people act by, with their desires."""
        return dataclasses.replace(
            ModelSettings(), beta=self.beta, hazard=self.hazard, desire_model=self.people
        )


def scenario(study: Study) -> Scenario:
    """paper-auto with people who act by the planner and start knowing, wrong or not knowing."""
    base = load_scenario("paper-auto")
    autonomy = dataclasses.replace(base.autonomy, planner="model", knows=study.knows, stale=study.stale)
    return dataclasses.replace(base, max_ticks=study.ticks, autonomy=autonomy)


def people_table(path: Path, scene: Scene, study: Study, rng: np.random.Generator) -> dict[str, list[float]]:
    """Write the policy table people act by to ``path``; returns each favourite goal's true
    utility vector (graded people: a graded-grid vector drawn among those whose one most
    wanted goal it is)."""
    settings = study.settings
    table = policy_table(scene, settings)
    goals = [str(g) for g in table["goals"]]
    truth = {g: list(map(float, u)) for g, u in zip(goals, solve_favourite(scene, settings), strict=True)}
    if study.people == "graded":
        u, qs = _graded_values(scene, settings)
        top = u.max(axis=1, keepdims=True)
        unique = np.isclose(u, top).sum(axis=1) == 1
        for d, goal in enumerate(goals):
            pick = int(rng.choice(np.flatnonzero(unique & np.isclose(u[:, d], top[:, 0]))))
            table["q"][d] = qs[pick].reshape(table["q"].shape[1:]).astype(np.float32)
            truth[goal] = list(map(float, u[pick]))
    with path.open("wb") as handle:
        np.savez(handle, **table)
    return truth


def solve_favourite(scene: Scene, settings: ModelSettings) -> np.ndarray:
    """``(D, D)`` one favourite's utility vectors (row ``d``: favourite ``d``)."""
    from brain.model.desires import favourite_utilities

    return favourite_utilities(settings, len(scene.items))


_VALUES: dict[tuple[str, ModelSettings], tuple[np.ndarray, np.ndarray]] = {}


def _graded_values(scene: Scene, settings: ModelSettings) -> tuple[np.ndarray, np.ndarray]:
    """``(U, D)`` the graded grid and ``(U, S, A)`` its Q-values (solved once per process)."""
    key = (scene.name, settings)
    if key not in _VALUES:
        _VALUES[key] = solve(build_world_model(scene), dataclasses.replace(settings, desire_model="graded"))
    return _VALUES[key]


def write_trace(path: Path, trace: Trace) -> Path:
    """``trace`` as a ``trace.jsonl`` that :func:`bridge.recording.trace.read_trace` reads back."""
    keys = Keys("synthetic")
    with path.open("w", encoding="utf-8") as handle:
        handle.write(trace_line(keys.info, trace.info) + "\n")
        for state, events in trace:
            handle.write(trace_line(keys.state, state) + "\n")
            handle.writelines(trace_line(keys.events, e) + "\n" for e in events)
    return path


def recordings(directory: Path, study: Study) -> tuple[list[Path], dict[str, Truth]]:
    """``study.episodes`` traces (seeds ``study.seed, ...``) in ``directory``, and each
    episode's truth (:class:`Truth`), by the trace's name."""
    directory.mkdir(parents=True, exist_ok=True)
    sc = scenario(study)
    scene = Engine(sc, check_policy=False).scene()
    paths, truths = [], {}
    for seed in range(study.seed, study.seed + study.episodes):
        table = directory / f"policy-s{seed}.npz"
        truth = Truth(people_table(table, scene, study, np.random.default_rng([seed, 39])))
        engine = Engine(sc, seed=seed, policy=load_policy_table(table))
        ticks = []
        for _ in range(sc.max_ticks):
            result = engine.step()
            ticks.append((result.state, result.events))
            truth.observe(engine, result.state.tick, [loc.id for loc in scene.locations])
        trace = Trace(engine.info("synthetic", ClockMode.LOCKSTEP), tuple(ticks))
        paths.append(write_trace(directory / f"synthetic-s{seed}.jsonl", trace))
        truths[paths[-1].stem] = truth
    return paths, truths


@dataclasses.dataclass
class Truth:
    """One episode's truth about its people: the utility vector of each favourite goal, each
    person's favourite from each tick it changed, and their belief after the first tick."""

    utilities: dict[str, list[float]]
    favourites: dict[str, list[tuple[int, str]]] = dataclasses.field(default_factory=dict)
    start: dict[str, list[list[float]]] = dataclasses.field(default_factory=dict)

    def observe(self, engine: Engine, tick: int, locations: Sequence[str]) -> None:
        """Take in the people after ``tick`` (their beliefs over ``locations``, in that order)."""
        for pid, person in engine.people.items():
            favourite = getattr(person, "preference", None)
            if favourite is None:
                continue
            changes = self.favourites.setdefault(pid, [])
            if not changes or changes[-1][1] != favourite:
                changes.append((tick, favourite))
            if pid not in self.start:
                belief = person.belief  # type: ignore[attr-defined]
                order = [belief.locations.index(loc) for loc in locations]
                self.start[pid] = [list(map(float, belief.of(item)[order])) for item in belief.items]

    def utility(self, person: str, tick: int) -> list[float]:
        """The person's utility vector at ``tick`` (their favourite then picks it)."""
        favourite = [goal for at, goal in self.favourites[person] if at <= tick]
        return self.utilities[favourite[-1] if favourite else self.favourites[person][0][1]]


def questions(trace: Trace, study: Study, truth: Truth) -> list[tuple[int, str, str, str, float]]:
    """Every question of one episode and its answer in ``[0, 1]`` as the raters read it
    (``study.read``: the generating model's smoothed estimate, or the ``truth``):
    ``(tick, person, quantity, target, x)``."""
    settings = study.settings
    tracker = MindTracker(trace.info.scene, settings)
    for state, events in trace:
        tracker.observe(state, events)
    scene = trace.info.scene
    items, places = [i.id for i in scene.items], [loc.id for loc in scene.locations]
    goals = [*items, "out"]
    low, high = goal_scale(settings, len(items))
    last = trace.ticks[-1][0].tick
    out = []
    for person in tracker.people:
        steps = tracker.tracks[person].steps
        if not steps:
            continue
        smoothed = tracker.smoothed(person)
        start = estimate_at(tracker, person, steps[0].tick, smoothed)
        assert start is not None
        believed = np.array(truth.start[person]) if study.read == "truth" else start.beliefs
        out += [
            (steps[0].tick, person, "belief", f"{item}@{place}", float(believed[k, j]))
            for k, item in enumerate(items)
            for j, place in enumerate(places)
        ]
        for n in range(1, study.desire_points + 1):
            tick = last * n // study.desire_points
            est = estimate_at(tracker, person, tick, smoothed)
            if est is None:
                continue
            wanted = utility(est, settings)
            if study.read == "truth":
                wanted = (np.array(truth.utility(person, tick)) - low) / (high - low)
            out += [(tick, person, "utility", goal, float(wanted[d])) for d, goal in enumerate(goals)]
    return out


def rate(paths: Sequence[Path], truths: dict[str, Truth], study: Study, path: Path) -> Path:
    """The raters' CSV of every episode's questions (see the module docstring)."""
    rng = np.random.default_rng([study.seed, 7])
    curves = np.exp(rng.normal(0.0, 0.3, size=study.raters))
    with path.open("w", newline="", encoding="utf-8") as handle:
        writer = csv.writer(handle)
        writer.writerow(COLUMNS)
        for recording in paths:
            for q, (tick, person, quantity, target, x) in enumerate(
                questions(read_trace(recording), study, truths[recording.stem])
            ):
                seen = np.clip(x, 0.0, 1.0) ** curves + rng.normal(0.0, study.noise, size=study.raters)
                values = np.clip(np.rint(1 + 6 * seen), 1, 7).astype(int)
                for r, value in enumerate(values):
                    row = (recording.stem, tick, person, quantity, target, value, "smoothed", f"r{r}", q)
                    writer.writerow(row)
    return path


def fit_ratings(
    paths: Sequence[Path], ratings: Path, study: Study, grid: str, out: Path, folds: int, workers: int
) -> dict:
    """``toyroom fit`` of ``beta`` over ``paths`` with the ratings (in this process); its ``fit.json``."""
    from toyroom.fitting.__main__ import main as fit_main

    argv = [
        *map(str, paths),
        "--params",
        "beta",
        "--grid",
        f"beta={grid}",
        "--set",
        f"hazard={study.hazard}",
        "--models",
        ",".join(MODELS),
        "--folds",
        str(folds),
        "--workers",
        str(workers),
        "--judgments",
        str(ratings),
        "--out",
        str(out),
        "--no-progress",
    ]
    code = fit_main(argv)
    if code != 0:
        raise SystemExit(f"toyroom fit failed ({code})")
    return json.loads((out / "fit.json").read_text(encoding="utf-8"))


def summary(fitted: dict, study: Study) -> dict[str, object]:
    """The study's numbers from ``fit.json``: each model's fitted beta (likelihood and
    judgments) and its ratio to the truth, each kind's r, and graded minus favourite."""
    first, second = MODELS
    judged = fitted["judgments"]
    out: dict[str, object] = {"generating_beta": study.beta}
    for model in MODELS:
        by_likelihood = fitted["models"][model]["fitted"]["beta"]
        by_ratings = judged[model]["fitted"]["beta"]
        out[model] = {
            "beta_likelihood": by_likelihood,
            "beta_judgments": by_ratings,
            "recovered_likelihood": abs(by_likelihood / study.beta - 1) <= 0.25,
            "recovered_judgments": abs(by_ratings / study.beta - 1) <= 0.25,
            "r": judged[model]["r"],
        }
    minus = judged[second]["minus_first"] or {}
    out[f"{first}_minus_{second}"] = {
        kind: {"mean": -d["mean"], "lo": -d["hi"], "hi": -d["lo"]} for kind, d in minus.items()
    }
    return out


def report(numbers: dict, seconds: dict[str, float]) -> str:
    """The numbers as lines of text."""
    first, second = MODELS
    lines = [f"generating beta {numbers['generating_beta']}; seconds: {seconds}"]
    for model in MODELS:
        m = numbers[model]
        lines.append(
            f"{model}: beta by likelihood {m['beta_likelihood']:g} "
            f"(within 25%: {m['recovered_likelihood']}), by ratings {m['beta_judgments']:g} "
            f"(within 25%: {m['recovered_judgments']})"
        )
        for kind, r in m["r"].items():
            lines.append(f"  r {kind}: {r['mean']:.4f} [{r['lo']:.4f}, {r['hi']:.4f}]")
    for kind, d in numbers[f"{first}_minus_{second}"].items():
        lines.append(
            f"{first} minus {second}, r {kind}: {d['mean']:+.4f} [{d['lo']:+.4f}, {d['hi']:+.4f}] "
            "(paired by episode)"
        )
    return "\n".join(lines)


def main(argv: Sequence[str] | None = None) -> dict[str, object]:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    defaults = Study()
    for field in dataclasses.fields(Study):
        flag = "--" + field.name.replace("_", "-")
        parser.add_argument(
            flag, type=type(getattr(defaults, field.name)), default=getattr(defaults, field.name)
        )
    parser.add_argument("--grid", default="1,2,3,4,5,6,8,12", help="the fit's beta grid")
    parser.add_argument("--folds", type=int, default=4)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--out", type=Path, help="keep the recordings, ratings and fit here")
    parser.add_argument("--json", type=Path, help="also write the numbers here")
    args = parser.parse_args(argv)
    study = Study(**{f.name: getattr(args, f.name) for f in dataclasses.fields(Study)})
    if study.people not in ("graded", "favourite"):
        parser.error(f"--people must be graded or favourite, not {study.people!r}")
    if study.read not in ("model", "truth"):
        parser.error(f"--read must be model or truth, not {study.read!r}")
    with tempfile.TemporaryDirectory() as scratch:
        root = args.out or Path(scratch)
        began = time.perf_counter()
        paths, truths = recordings(root / "recordings", study)
        generated = time.perf_counter() - began
        ratings = rate(paths, truths, study, root / "ratings.csv")
        kept = {
            "study": dataclasses.asdict(study),
            "truths": {k: dataclasses.asdict(t) for k, t in truths.items()},
        }
        (root / "truths.json").write_text(json.dumps(kept), encoding="utf-8")
        rated = time.perf_counter() - began - generated
        fitted = fit_ratings(paths, ratings, study, args.grid, root / "fit", args.folds, args.workers)
    seconds = {"generate": round(generated, 1), "rate": round(rated, 1)}
    seconds["fit"] = round(time.perf_counter() - began - generated - rated, 1)
    numbers = summary(fitted, study) | {"study": dataclasses.asdict(study), "seconds": seconds}
    print(report(numbers, seconds))
    sys.stdout.flush()
    if args.json:
        args.json.write_text(json.dumps(numbers, indent=2), encoding="utf-8")
    return numbers


if __name__ == "__main__":
    main()
