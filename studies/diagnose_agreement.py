"""Why graded desires and the belief-space planner agree with ratings as they do: on episodes
of simulated people (``studies/rate_synthetic_people.py``'s: the paper map, two people who act by
the planner, graded desires by default), ratings made from the people's TRUE beliefs and
utilities, and several observer configurations read on the same episodes, paired.

Each configuration (``--configs``, comma-separated) is
``PLANNER-DESIRES[-LEVELS][-unique]``:
``person_planner`` (``qmdp``, the default, or ``belief``), ``desire_model`` (``graded`` or
``favourite``), graded desires' ``desire_levels`` (3 unless given) and ``unique`` (the grid
without the candidates whose top goal is tied: the support the simulated people are drawn
from, an oracle prior; the candidates are patched in this process only). All at the
study's beta and hazard. The first configuration is the reference. (A ``hazardfirst``
option once patched the exact graded model to apply the preference switch of the pause
before a decision before that decision's likelihood; every model now does, so it is gone.)

Questions (``K`` items, ``L`` locations, ``D = K + 1`` goals) of each person, each answered by
``--raters`` raters as ``synthetic_ratings`` does (``clip(round(1 + 6 (x**g + N(0, noise))),
1, 7)``, ``g = exp(N(0, 0.3))``) from the truth ``x`` and averaged:

- ``belief start``: P(believes item ``k`` at ``l``) at the person's first step (the
  synthetic study's belief question); ``belief middle``, ``belief end``: at the person's last
  step at or before the middle and the last tick (their true belief at that step);
- ``utility``: each goal's true utility on its scale at the middle and the last tick (the
  synthetic study's utility question), read off the estimate as the posterior mean utility
  (``E[u]``), as P(most wanted) (``P(top)``) or as minus the expected rank (``-rank``).

Every question is read off the smoothed and the online estimate. Printed: each kind's r with
the ratings (bootstrap 95% interval over episodes), each configuration minus the reference
(and each ``belief-*`` minus its ``qmdp-*``) paired by episode; the same r against the
noise-free truth; the beliefs' calibration against the true beliefs (Brier score: mean
squared difference per item and location; mean entropy in bits per person and item; the
share of person-items the estimate is sure of (max above 0.95) where the truth is not, and
the reverse); and the episodes that carry the largest paired differences.

    python studies/diagnose_agreement.py [--episodes 24] [--seed 0] [--ticks 1000]
        [--people graded] [--configs qmdp-graded,belief-graded,qmdp-favourite,belief-favourite]
        [--json FILE]
"""

from __future__ import annotations

import argparse
import contextlib
import dataclasses
import importlib.util
import json
import sys
import time
from collections.abc import Iterator, Sequence
from pathlib import Path
from types import ModuleType

import numpy as np

from brain.model import desires, lookahead, planner
from brain.model.arrays import FloatArray
from brain.model.estimates import Estimate
from brain.settings import ModelSettings
from brain.tracking.tracker import MindTracker
from bridge.recording.trace import Trace
from protocol import ClockMode
from sim2d.engine import Engine
from sim2d.people import load_policy_table
from toyroom.fitting.correlation import paired_difference, pearson
from toyroom.fitting.judged import estimate_at, expected_rank, goal_scale, utility

DEFAULT_CONFIGS = "qmdp-graded,belief-graded,qmdp-favourite,belief-favourite"
SURE = 0.95
"""A belief row is sure when its largest probability is above this."""


def _synthetic() -> ModuleType:
    """``studies/rate_synthetic_people.py`` (a sibling script, not a package)."""
    name = "rate_synthetic_people"
    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(name, Path(__file__).with_name(f"{name}.py"))
        assert spec is not None and spec.loader is not None
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module  # its dataclasses look their module up
        spec.loader.exec_module(module)
    return sys.modules[name]


@dataclasses.dataclass(frozen=True)
class Config:
    """One observer configuration (see the module docstring)."""

    name: str
    planner: str
    desires: str
    levels: int = 3
    unique: bool = False

    @classmethod
    def parse(cls, name: str) -> Config:
        parts = name.split("-")
        if len(parts) < 2 or parts[0] not in ("qmdp", "belief") or parts[1] not in ("graded", "favourite"):
            raise ValueError(f"a configuration is PLANNER-DESIRES[-LEVELS][-unique], not {name!r}")
        levels, unique = 3, False
        for part in parts[2:]:
            if part == "unique":
                unique = True
            elif part.isdigit() and int(part) >= 2:
                levels = int(part)
            else:
                raise ValueError(f"unknown part {part!r} of configuration {name!r}")
        if parts[1] == "favourite" and (unique or levels != 3):
            raise ValueError(f"levels and unique are for graded desires: {name!r}")
        return cls(name, parts[0], parts[1], levels, unique)

    def settings(self, base: ModelSettings) -> ModelSettings:
        return dataclasses.replace(
            base, person_planner=self.planner, desire_model=self.desires, desire_levels=self.levels
        )


@contextlib.contextmanager
def unique_top(active: bool) -> Iterator[None]:
    """Within: graded candidates whose most wanted goal is tied are left out of the grid
    (patched into the planners of this process; their caches cleared on entry and exit)."""

    def clear() -> None:
        planner.cached_policy.cache_clear()
        planner._cached_values.cache_clear()
        lookahead.cached_lookahead.cache_clear()

    if not active:
        yield
        return
    real = desires.utilities

    def untied(settings: ModelSettings, n_items: int, leaves: bool = True) -> FloatArray:
        u = real(settings, n_items, leaves)
        top = u.max(axis=1, keepdims=True)
        return u[np.isclose(u, top).sum(axis=1) == 1]

    clear()
    planner.utilities, lookahead.utilities = untied, untied
    try:
        yield
    finally:
        planner.utilities, lookahead.utilities = real, real
        clear()


@dataclasses.dataclass
class Episode:
    """One recorded episode and the truth about its people: their beliefs ``(K, L)`` at every
    tick, their utility vectors (``synthetic_ratings.Truth``)."""

    trace: Trace
    truth: object
    beliefs: dict[str, dict[int, FloatArray]]


def episodes(study: object) -> list[Episode]:
    """``study.episodes`` episodes (seeds ``study.seed, ...``), in memory."""
    sr = _synthetic()
    sc = sr.scenario(study)
    scene = Engine(sc, check_policy=False).scene()
    places = [loc.id for loc in scene.locations]
    out = []
    with _scratch() as folder:
        for seed in range(study.seed, study.seed + study.episodes):  # type: ignore[attr-defined]
            table = folder / f"policy-s{seed}.npz"
            truth = sr.Truth(sr.people_table(table, scene, study, np.random.default_rng([seed, 39])))
            engine = Engine(sc, seed=seed, policy=load_policy_table(table))
            ticks = []
            beliefs: dict[str, dict[int, FloatArray]] = {}
            for _ in range(sc.max_ticks):
                result = engine.step()
                ticks.append((result.state, result.events))
                truth.observe(engine, result.state.tick, places)
                for pid, person in engine.people.items():
                    belief = getattr(person, "belief", None)
                    if belief is not None:
                        order = [belief.locations.index(loc) for loc in places]
                        now = np.array([belief.of(item)[order] for item in belief.items])
                        beliefs.setdefault(pid, {})[result.state.tick] = now
            trace = Trace(engine.info("synthetic", ClockMode.LOCKSTEP), tuple(ticks))
            out.append(Episode(trace, truth, beliefs))
    return out


@contextlib.contextmanager
def _scratch() -> Iterator[Path]:
    import tempfile

    with tempfile.TemporaryDirectory() as folder:
        yield Path(folder)


@dataclasses.dataclass
class Question:
    """One rated quantity: its episode, kind (``belief start``, ...), person, step tick, the
    row it reads (``(k, l)`` or the goal ``d``) and the true value ``x`` in [0, 1]."""

    episode: int
    kind: str
    person: str
    tick: int
    index: tuple[int, ...]
    x: float


def questions(
    eps: Sequence[Episode], tracker_of: list[MindTracker], settings: ModelSettings
) -> list[Question]:
    """Every question of every episode (the trackers give each person's steps)."""
    out = []
    for e, ep in enumerate(eps):
        tracker = tracker_of[e]
        items = ep.trace.info.scene.items
        low, high = goal_scale(settings, len(items))
        last = ep.trace.ticks[-1][0].tick
        for person in tracker.people:
            steps = [s.tick for s in tracker.tracks[person].steps]
            if not steps:
                continue
            start = np.array(ep.truth.start[person])  # type: ignore[attr-defined]
            times = {"start": (steps[0], start)}
            for label, tick in (("middle", last // 2), ("end", last)):
                at = max(t for t in steps if t <= tick) if steps[0] <= tick else None
                if at is not None:
                    times[label] = (at, ep.beliefs[person][at])
            for label, (tick, believed) in times.items():
                out += [
                    Question(e, f"belief {label}", person, tick, (k, j), float(believed[k, j]))
                    for k in range(believed.shape[0])
                    for j in range(believed.shape[1])
                ]
            for tick in (last // 2, last):
                if steps[0] > tick:
                    continue
                u = (np.array(ep.truth.utility(person, tick)) - low) / (high - low)  # type: ignore[attr-defined]
                out += [Question(e, "utility", person, tick, (d,), float(u[d])) for d in range(len(u))]
    return out


READINGS = ("E[u]", "P(top)", "-rank")


def read(est: Estimate, q: Question, settings: ModelSettings, reading: str) -> float:
    """The estimate's value of question ``q`` (a utility question read as ``reading``)."""
    if q.kind.startswith("belief"):
        return float(est.beliefs[q.index])
    if reading == "E[u]":
        return float(utility(est, settings)[q.index])
    if reading == "P(top)":
        return float(est.preference[q.index])
    return -float(expected_rank(est)[q.index])


def answers(
    eps: Sequence[Episode], qs: Sequence[Question], settings: ModelSettings
) -> tuple[dict[str, FloatArray], FloatArray]:
    """Each kind of prediction ``(N,)`` (``smoothed belief start``, ``online utility E[u]``,
    ...; ``nan`` where it does not apply) and each smoothed belief question's estimated row
    ``(N, L)`` (for calibration), under ``settings``."""
    n = len(qs)
    out: dict[str, FloatArray] = {}
    rows = {"smoothed": np.full((n, 0), np.nan), "online": np.full((n, 0), np.nan)}
    by_episode: dict[int, list[int]] = {}
    for i, q in enumerate(qs):
        by_episode.setdefault(q.episode, []).append(i)
    for e, ep in enumerate(eps):
        tracker = track(ep.trace, settings)
        smoothed = {p: tracker.smoothed(p) for p in tracker.people if tracker.tracks[p].steps}
        for i in by_episode.get(e, []):
            q = qs[i]
            for how in ("smoothed", "online"):
                est = estimate_at(
                    tracker, q.person, q.tick, smoothed[q.person] if how == "smoothed" else None
                )
                if est is None:
                    continue
                if rows[how].shape[1] == 0:
                    rows[how] = np.full((n, est.beliefs.shape[1]), np.nan)
                if q.kind.startswith("belief"):
                    out.setdefault(f"{how} {q.kind}", np.full(n, np.nan))[i] = read(est, q, settings, "")
                    rows[how][i] = est.beliefs[q.index[0]]
                else:
                    for reading in READINGS:
                        value = read(est, q, settings, reading)
                        out.setdefault(f"{how} utility {reading}", np.full(n, np.nan))[i] = value
    return out, rows["smoothed"]


def track(trace: Trace, settings: ModelSettings) -> MindTracker:
    tracker = MindTracker(trace.info.scene, settings)
    for state, events in trace:
        tracker.observe(state, events)
    return tracker


def ratings(qs: Sequence[Question], raters: int, noise: float, seed: int) -> FloatArray:
    """``(N,)`` each question's mean rating on 1-7 (``synthetic_ratings.rate``'s raters)."""
    rng = np.random.default_rng([seed, 7])
    curves = np.exp(rng.normal(0.0, 0.3, size=raters))
    out = np.empty(len(qs))
    for i, q in enumerate(qs):
        seen = np.clip(q.x, 0.0, 1.0) ** curves + rng.normal(0.0, noise, size=raters)
        out[i] = np.clip(np.rint(1 + 6 * seen), 1, 7).mean()
    return out


def calibration(
    qs: Sequence[Question], rows: FloatArray, truth_rows: FloatArray
) -> dict[str, dict[str, float]]:
    """Per time of the belief questions: Brier score, mean entropy (bits) of the estimate
    and of the truth per person-item, and the shares of person-items sure in one and not the
    other."""
    out = {}
    for label in ("start", "middle", "end"):
        mine = [i for i, q in enumerate(qs) if q.kind == f"belief {label}" and q.index[1] == 0]
        if not mine:
            continue
        est, true = rows[mine], truth_rows[mine]
        ok = np.isfinite(est).all(axis=1)
        est, true = est[ok], true[ok]
        sure_est, sure_true = est.max(axis=1) > SURE, true.max(axis=1) > SURE
        out[label] = {
            "brier": float(np.mean((est - true) ** 2)),
            "entropy": _entropy(est),
            "true entropy": _entropy(true),
            "sure, truth not": float(np.mean(sure_est & ~sure_true)),
            "truth sure, estimate not": float(np.mean(~sure_est & sure_true)),
        }
    return out


def _entropy(p: FloatArray) -> float:
    safe = np.where(p > 0, p, 1.0)
    return float(np.mean(-(p * np.log2(safe)).sum(axis=1)))


def truth_rows(eps: Sequence[Episode], qs: Sequence[Question]) -> FloatArray:
    """``(N, L)`` each belief question's true row (the person's belief about the item)."""
    width = max(len(ep.trace.info.scene.locations) for ep in eps)
    out = np.full((len(qs), width), np.nan)
    for i, q in enumerate(qs):
        if not q.kind.startswith("belief"):
            continue
        ep = eps[q.episode]
        at = np.array(ep.truth.start[q.person]) if q.kind == "belief start" else ep.beliefs[q.person][q.tick]  # type: ignore[attr-defined]
        out[i] = at[q.index[0]]
    return out


def influence(
    pred: FloatArray, other: FloatArray, values: FloatArray, episode: np.ndarray
) -> list[tuple[int, float]]:
    """The three episodes whose leaving out moves the pooled ``r(pred) - r(other)`` most:
    ``(episode, the difference without it minus with it)``."""
    whole = pearson(pred, values) - pearson(other, values)
    moves = []
    for e in np.unique(episode):
        keep = episode != e
        moves.append((int(e), pearson(pred[keep], values[keep]) - pearson(other[keep], values[keep]) - whole))
    return sorted(moves, key=lambda m: -abs(m[1]))[:3]


def diagnose(study: object, configs: Sequence[Config], raters: int, noise: float) -> dict[str, object]:
    """Every number the module docstring lists."""
    began = time.perf_counter()
    eps = episodes(study)
    base: ModelSettings = study.settings  # type: ignore[attr-defined]
    generated = time.perf_counter() - began
    reference = [track(ep.trace, base) for ep in eps]
    qs = questions(eps, reference, base)
    episode = np.array([q.episode for q in qs])
    truth = np.array([q.x for q in qs])
    rated = ratings(qs, raters, noise, study.seed)  # type: ignore[attr-defined]
    true_rows = truth_rows(eps, qs)
    preds: dict[str, dict[str, FloatArray]] = {}
    calib: dict[str, object] = {}
    seconds = {"generate": round(generated, 1)}
    for config in configs:
        began = time.perf_counter()
        with unique_top(config.unique):
            preds[config.name], rows = answers(eps, qs, config.settings(base))
        calib[config.name] = calibration(qs, rows, true_rows)
        seconds[config.name] = round(time.perf_counter() - began, 1)
    kinds = sorted(preds[configs[0].name])
    out: dict[str, object] = {"questions": len(qs), "episodes": len(eps), "seconds": seconds}
    for target, values in (("ratings", rated), ("truth", truth)):
        r: dict[str, object] = {}
        for config in configs:
            r[config.name] = _by_kind(preds[config.name], None, values, episode, kinds)
        r["differences"] = {
            f"{a} - {b}": _by_kind(preds[a], preds[b], values, episode, kinds)
            for a, b in _pairs([c.name for c in configs])
        }
        out[target] = r
    out["calibration"] = calib
    out["influence"] = {
        f"{a} - {b}": {
            kind: influence(preds[a][kind], preds[b][kind], rated, episode) for kind in _main_kinds(kinds)
        }
        for a, b in _pairs([c.name for c in configs])
    }
    out["per_episode"] = {
        f"{a} - {b}": {
            kind: _per_episode(preds[a][kind], preds[b][kind], rated, episode) for kind in _main_kinds(kinds)
        }
        for a, b in _pairs([c.name for c in configs])
    }
    return out


def _main_kinds(kinds: Sequence[str]) -> list[str]:
    return [k for k in ("smoothed belief start", "smoothed utility E[u]") if k in kinds]


def _by_kind(
    pred: dict[str, FloatArray],
    other: dict[str, FloatArray] | None,
    values: FloatArray,
    episode: np.ndarray,
    kinds: Sequence[str],
) -> dict[str, dict[str, float]]:
    """Each prediction kind's r (or r minus ``other``'s, paired by episode) over its rows."""
    out = {}
    for kind in kinds:
        rows = np.flatnonzero(np.isfinite(pred[kind]))
        labels = [kind] * len(rows)
        against = None if other is None else other[kind][rows]
        out[kind] = paired_difference(pred[kind][rows], against, values[rows], labels, episode[rows], 0)[kind]
    return out


def _pairs(names: Sequence[str]) -> list[tuple[str, str]]:
    """Each configuration against the first, and each ``belief-X`` against its ``qmdp-X``."""
    pairs = [(n, names[0]) for n in names[1:]]
    for n in names:
        twin = "qmdp" + n[len("belief") :]
        if n.startswith("belief") and twin in names and (n, twin) not in pairs:
            pairs.append((n, twin))
    return pairs


def _per_episode(
    pred: FloatArray, other: FloatArray, values: FloatArray, episode: np.ndarray
) -> dict[str, float]:
    """The within-episode differences of r: median, and how many episodes differ by more
    than 0.05 either way (and how many have an r at all)."""
    diffs = []
    for e in np.unique(episode):
        rows = episode == e
        d = pearson(pred[rows], values[rows]) - pearson(other[rows], values[rows])
        if np.isfinite(d):
            diffs.append(d)
    a = np.array(diffs)
    return {
        "episodes": len(a),
        "median": float(np.median(a)) if len(a) else float("nan"),
        "below -0.05": int((a < -0.05).sum()),
        "above +0.05": int((a > 0.05).sum()),
    }


def report(numbers: dict) -> str:
    """The numbers as lines of text."""
    lines = [
        f"{numbers['episodes']} episodes, {numbers['questions']} questions; seconds {numbers['seconds']}"
    ]
    for target in ("ratings", "truth"):
        block = numbers[target]
        names = [n for n in block if n != "differences"]
        lines.append(
            f"r with the {target}: " + " | ".join([*names, *(f"{d} (paired)" for d in block["differences"])])
        )
        for kind in block[names[0]]:
            cells = [_ci(block[n][kind]) for n in names]
            cells += [_ci(d[kind], sign=True) for d in block["differences"].values()]
            lines.append(f"  {kind}: " + " | ".join(cells))
    lines.append("belief calibration against the true beliefs (smoothed):")
    for name, times in numbers["calibration"].items():
        lines.append(
            f"  {name}: "
            + "; ".join(
                f"{t}: " + ", ".join(f"{k} {v:.4f}" for k, v in row.items()) for t, row in times.items()
            )
        )
    lines.append("largest leave-one-episode-out moves of the paired difference (ratings):")
    for pair, kinds in numbers["influence"].items():
        for kind, moves in kinds.items():
            per = numbers["per_episode"][pair][kind]
            lines.append(
                f"  {pair}, {kind}: "
                + ", ".join(f"episode {e} {m:+.4f}" for e, m in moves)
                + f"; per episode: median {per['median']:+.4f}, {per['below -0.05']} below -0.05, "
                f"{per['above +0.05']} above +0.05 of {per['episodes']}"
            )
    return "\n".join(lines)


def _ci(v: dict[str, float], sign: bool = False) -> str:
    f = "+.4f" if sign else ".4f"
    return f"{v['mean']:{f}} [{v['lo']:{f}}, {v['hi']:{f}}]"


def main(argv: Sequence[str] | None = None) -> dict[str, object]:
    sr = _synthetic()
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes", type=int, default=24)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--ticks", type=int, default=1000)
    parser.add_argument("--people", default="graded", choices=("graded", "favourite"))
    parser.add_argument("--beta", type=float, default=sr.Study.beta)
    parser.add_argument("--hazard", type=float, default=sr.Study.hazard)
    parser.add_argument("--raters", type=int, default=8)
    parser.add_argument("--noise", type=float, default=0.1)
    parser.add_argument("--configs", default=DEFAULT_CONFIGS)
    parser.add_argument("--json", type=Path, help="also write the numbers here")
    args = parser.parse_args(argv)
    try:
        configs = [Config.parse(c) for c in args.configs.split(",")]
    except ValueError as err:
        parser.error(str(err))
    study = sr.Study(
        episodes=args.episodes,
        ticks=args.ticks,
        beta=args.beta,
        hazard=args.hazard,
        people=args.people,
        seed=args.seed,
        read="truth",
    )
    numbers = diagnose(study, configs, args.raters, args.noise)
    numbers["study"] = dataclasses.asdict(study) | {"configs": args.configs}
    print(report(numbers))
    sys.stdout.flush()
    if args.json:
        args.json.write_text(json.dumps(numbers, indent=2), encoding="utf-8")
    return numbers


if __name__ == "__main__":
    main()
