"""docs/performance.md, generated from ``bench.json``: a table of the numbers
against their targets, the scaling table and ``scaling.png``.

    python -m toyroom.bench.perfreport DIR/bench.json \
        [--readme docs/performance.md --figure docs/perf/scaling.png]

Writes ``DIR/perf.md`` and ``DIR/scaling.png``; with ``--readme``, replaces the text between
``<!-- perf:start -->`` and ``<!-- perf:end -->`` in the README and copies the figure to
``--figure`` (the path the README links).
"""

from __future__ import annotations

import argparse
import json
import shutil
from pathlib import Path
from typing import Any

START, END = "<!-- perf:start -->", "<!-- perf:end -->"
REVIEW_ENGINE_STEP_US = (154, 430)
"""The engine's tick alone as the review measured it (``../shared/REVIEW.md``, section 6),
the anchor of the target "halved"."""
EMBODIED_FIGURES = (
    ("peak GiB", "peak_gib", ".2f"),
    ("first look s", "first_look_s", ".2f"),
    ("tick ms, mean", "tick_ms", ".1f"),
    ("tick ms, p99", "tick_p99_ms", ".1f"),
)
"""The households' embodied row (:mod:`.embodied`): each figure's name, key and format."""


def plot(numbers: dict[str, Any], path: Path) -> None:
    """Step time and planner time against the number of worlds, exact and factored."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = numbers["scaling"]
    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 3.6))
    worlds = [r["worlds"] for r in rows]
    used = ["exact" if r["exact"] else "factored" for r in rows]
    for ax, key, exact_key, unit, target in (
        (left, "step_us", "exact_step_us", "online step per person (ms)", 20.0),
        (right, "planner_s", "exact_planner_s", "planner, cold (s)", 30.0),
    ):
        scale = 1e-3 if key == "step_us" else 1.0
        ax.plot(worlds, [r[key] * scale for r in rows], "o-", color="#4C72B0", label="as run (auto)")
        for w, r, kind in zip(worlds, rows, used, strict=True):
            ax.annotate(
                f"{r['rooms']}r/{r['items']}i\n{kind}",
                (w, r[key] * scale),
                fontsize=7,
                textcoords="offset points",
                xytext=(4, 4),
            )
        exact = [(r["worlds"], r[exact_key] * scale) for r in rows if r.get(exact_key) is not None]
        if exact:
            ax.plot(*zip(*exact, strict=True), "s--", color="#C44E52", label="exact model")
        ax.axhline(target, color="#8C8C8C", linestyle=":", label=f"target ({target:g})")
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_xlabel("worlds W = (2 locations)^items")
        ax.set_ylabel(unit)
        ax.legend(fontsize=7)
    fig.suptitle("the brain on generated houses (toyroom bench)", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def _graded_rows(numbers: dict[str, Any]) -> list[str]:
    """The graded belief model's rows (absent from runs made before it existed)."""
    graded = numbers.get("graded")
    if graded is None:
        return []
    step = graded["brain_step_us"]
    return [
        "| `graded.brain_step_us` median / p99, paper map, graded beliefs (the default) | "
        f"{step['median']:.0f} / "
        f"{step['p99']:.0f} | <= 1000 |",
        f"| `graded.planner_cold_s`, paper map, graded beliefs | {graded['planner_cold_s']:.3f} | <= 2 |",
    ]


def _gateway_rows(numbers: dict[str, Any]) -> list[str]:
    """The gateway's rows (:mod:`.gateway`), when the run measured them (the grid engines'
    ticks need a source checkout)."""
    if "gateway" not in numbers:
        return []
    gateway, profile = numbers["gateway"], numbers["lockstep_profile"]
    ticks = gateway["lockstep_tick_us"]
    rows = [
        f"| gateway: a query answered by a WebSocket client | {gateway['query_rtt_us']:.0f} "
        f"| (a Zenoh process: {profile['zenoh_query_two_processes_us']:.0f}) |",
    ]
    if "direct" in ticks:
        rows += [
            f"| grid engine lock-step tick over Zenoh | {ticks['direct']:.0f} | |",
            f"| the same engine through the gateway | {ticks['gateway']:.0f} "
            f"| <= {2 * ticks['direct']:.0f} (2 x direct): {ticks['ratio']:.2f} x |",
        ]
    if "csharp" in ticks:
        rows.append(f"| the C# SDK's grid engine (Mono) through the gateway | {ticks['csharp']:.0f} | |")
    return rows


def _eval_rows(numbers: dict[str, Any]) -> list[str]:
    """The evaluation's speed, when the run measured it."""
    if "eval_timing" not in numbers:
        return []
    timing = numbers["eval_timing"]
    runs = ", ".join(f"{name} {seconds:.1f} s" for name, seconds in timing["run_seconds_mean"].items())
    return [
        f"| `eval_seconds_per_episode`: `toyroom eval`, {timing['episodes']} episodes, "
        f"{timing['workers']} workers | {timing['seconds_per_episode']:.2f} | <= 1.2 (500 in 10 min) |",
        f"| of which, each run's mean wall time ({timing['workers']} at a time): {runs} | | |",
        *_eval_cpu_row(timing),
    ]


def _eval_cpu_row(timing: dict[str, Any]) -> list[str]:
    """The evaluation's CPU seconds per episode, when the run measured them."""
    cpu = timing.get("cpu_seconds_per_episode")
    if not cpu:
        return []
    total = sum(cpu.values())
    return [
        f"| CPU seconds per episode: the node processes {cpu['nodes']:.1f}, the evaluator "
        f"{cpu['evaluator']:.1f} (so at least {total / 2:.1f} s of wall per episode on 2 cores) "
        f"| {total:.1f} | <= 2.4 for 1.2 s on 2 cores |"
    ]


def _lockstep_rows(numbers: dict[str, Any]) -> list[str]:
    """The lock-step tick against the raw query: interleaved in the same run where it was
    (:mod:`.lockstep`), else one after the other (runs made before)."""
    tick, profile = numbers["lockstep_tick_us"], numbers["lockstep_profile"]
    query = profile["zenoh_query_two_processes_us"]
    mixed = profile.get("interleaved")
    if mixed is None:
        return [
            f"| `lockstep_tick_us`: step one tick, get its state | {tick:.0f} "
            f"| <= {1.5 * query:.0f} (1.5 x the raw query): {tick / query:.2f} x |"
        ]
    return [
        f"| `lockstep_tick_us`: step one tick, get its state (interleaved with the raw query, "
        f"{mixed['blocks']} blocks of {mixed['rounds_per_block']} of each) | {tick:.0f} "
        f"| <= 1.5 x the raw query: {mixed['ratio']:.2f} x "
        f"[{mixed['ratio_lo']:.2f}, {mixed['ratio_hi']:.2f}] |"
    ]


def _lockstep_profile_rows(profile: dict[str, Any]) -> list[str]:
    """The raw query, the bridge's typed query with no engine behind it, and the CPU of
    each side per round trip (rows from runs that measured them)."""
    rows = [
        f"| of which: raw query between two processes | {profile['zenoh_query_two_processes_us']:.0f} | |"
    ]
    mixed = profile.get("interleaved")
    if mixed is None:
        return rows
    cpu = mixed["cpu_us_per_round_trip"]
    return [
        *rows,
        f"| of which: the bridge's typed query answered with a fixed state, no engine "
        f"(`toyroom/toyroom/bench/typed_echo.py`) | {profile['typed_query_us']:.0f} "
        f"| {mixed['typed_query_ratio']:.2f} x the raw query "
        f"[{mixed['typed_query_ratio_lo']:.2f}, {mixed['typed_query_ratio_hi']:.2f}] |",
        f"| CPU per round trip, answering side / asking side, us: raw query {cpu['query_peer']:.0f} / "
        f"{cpu['query_client']:.0f}, typed query {cpu['typed_query_peer']:.0f} / "
        f"{cpu['typed_query_client']:.0f}, lock-step tick {cpu['tick_peer']:.0f} / "
        f"{cpu['tick_client']:.0f} | | |",
    ]


def _engine_against_review(profile: dict[str, Any]) -> list[str]:
    """The engine's tick against the review's commit, interleaved in the same run."""
    then = profile.get("engine_step_vs_review")
    if then is None:
        return []
    return [
        f"| the same, CPU time per tick now / at the review's `{then['commit']}`, interleaved "
        f"(`toyroom/toyroom/bench/engine_ab.py`) | {then['now_us']:.0f} / {then['then_us']:.0f} "
        f"| <= 0.5 x: {then['ratio']:.2f} x [{then['ratio_lo']:.2f}, {then['ratio_hi']:.2f}] |"
    ]


def _household_rows(numbers: dict[str, Any]) -> list[str]:
    """The households table: the default (graded) model per tick for all people together,
    its smoother and its memory (rows from runs that measured them)."""
    rows = [r for r in numbers["scaling"] if "tick_us" in r]
    if not rows:
        return []
    lines = [
        "",
        "Households: the default (graded) model per tick for all people together, their nested "
        "beliefs about each other included (every ordered pair of people: 56 with 8), and "
        "without them (mean, median, p99 over the episode's ticks; target with them: mean <= 20 "
        "ms and p99 <= 50 ms), the time to smooth every person's "
        "whole episode, the smoothed estimate's TV against the exact model's forward-backward "
        "(graded; point in brackets) where that fits, and the tracker's memory per person at the "
        "end (its filters, and every step's record and estimate, which `mind.csv` and the "
        "smoother read).",
        "",
        "| rooms | items | people | model | tick ms: mean / median / p99 | first-order alone: mean / p99 "
        "| smoothing s | smoothed tv vs exact (point) | memory per person MB |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        smoothed = r["smoothed"]
        tv = "-" if smoothed["tv_vs_exact"] is None else f"{smoothed['tv_vs_exact']:.4f}"
        if smoothed["point_tv_vs_exact"] is not None:
            tv += f" ({smoothed['point_tv_vs_exact']:.4f})"
        lines.append(
            f"| {r['rooms']} | {r['items']} | {r['people']} | {'exact' if r['exact'] else 'factored'} "
            f"| {r['tick_us'] / 1e3:.1f} / {r['tick_median_us'] / 1e3:.1f} / {r['tick_p99_us'] / 1e3:.1f} "
            f"| {r['first_order_tick_us'] / 1e3:.1f} / {r['first_order_tick_p99_us'] / 1e3:.1f} "
            f"| {smoothed['seconds']:.2f} | {tv} | {r['memory_per_person_bytes'] / 2**20:.1f} |"
        )
    return lines


def _embodied_rows(numbers: dict[str, Any]) -> list[str]:
    """The households' embodied row (issue 66), embodied beside omniscient (none in a
    ``bench.json`` from before it)."""
    row = numbers.get("households_embodied")
    if row is None:
        return []
    lines = [
        "",
        f"Households with a robot that sees only what its own cell sees "
        f"(`toyroom/bench/embodied.py`): {row['rooms']} rooms, {row['items']} items, {row['people']} "
        f"people, lapses on (`miss` {row['miss']:g}), {row['ticks']} ticks; the same robot seeing "
        "everything beside it. Peak: the process's resident set; first look: the robot's first "
        "tick, where every filter is made; the tick: every later one.",
        "",
        "| figure | embodied | omniscient | target |",
        "|---|---|---|---|",
    ]
    for name, key, form in EMBODIED_FIGURES:
        lines.append(
            f"| {name} | {row['embodied'][key]:{form}} | {row['omniscient'][key]:{form}} "
            f"| <= {row['targets'][key]:g} |"
        )
    return lines


def _scaling_rows(numbers: dict[str, Any]) -> list[str]:
    """The scaling table's rows, a generated house each."""
    lines: list[str] = []
    for r in numbers["scaling"]:
        exact = "-" if r["exact_step_us"] is None else f"{r['exact_planner_s']:.2f}, {r['exact_step_us']:.0f}"
        tv = "-" if r["tv_vs_exact"] is None else f"{r['tv_vs_exact']:.4f}"
        ptv = "-" if r["preference_tv_vs_exact"] is None else f"{r['preference_tv_vs_exact']:.4f}"
        graded = (
            f"{r['graded_step_us']:.0f} ({r['graded_step_p99_us']:.0f})" if "graded_step_us" in r else "-"
        )
        gtv = "-" if r.get("graded_tv_vs_exact") is None else f"{r['graded_tv_vs_exact']:.4f}"
        lines.append(
            f"| {r['rooms']} | {r['items']} | {r['worlds']:.3g} | {'exact' if r['exact'] else 'factored'} "
            f"| {r['planner_s']:.2f} | {r['step_us']:.0f} ({r['step_p99_us']:.0f}) | {exact} | {tv} | {ptv} "
            f"| {graded} | {gtv} |"
        )
    return lines


def markdown(numbers: dict[str, Any], figure: str, command: str) -> str:
    """The section's text."""
    zenoh = numbers["zenoh_rtt_us"]
    step = numbers["brain_step_us"]
    profile = numbers["lockstep_profile"]
    lines = [
        f"Measured on this project's 2-core machine by `{command}`; every number below is from "
        "one run (compare ratios, not absolute times, across machines).",
        "",
        "| measure | value | target |",
        "|---|---|---|",
        f"| `zenoh_rtt_us`: raw zenoh-python ping-pong, {numbers['payload_bytes']} B | {zenoh:.0f} | |",
        f"| `bridge_rtt_us`: the same with typed messages | {numbers['bridge_rtt_us']:.0f} | |",
        *_lockstep_rows(numbers),
        f"| `lockstep_ticks_per_s` | {numbers['lockstep_ticks_per_s']:.0f} | |",
        f"| of which: raw ping-pong between two processes | {profile['zenoh_rtt_two_processes_us']:.0f} | |",
        *_lockstep_profile_rows(profile),
        f"| of which: the engine's tick alone (`paper-auto`) | {profile['engine_step_us']:.0f} "
        f"| half the review's {REVIEW_ENGINE_STEP_US[0]}-{REVIEW_ENGINE_STEP_US[1]} |",
        *_engine_against_review(profile),
        *_gateway_rows(numbers),
        *_eval_rows(numbers),
        "| `brain_step_us` median / p99, paper map, point beliefs | "
        f"{step['median']:.0f} / {step['p99']:.0f} | <= 1000 |",
        f"| `planner_cold_s`, paper map, point beliefs | {numbers['planner_cold_s']:.3f} | <= 0.5 |",
        *_graded_rows(numbers),
        "",
        "Scaling: generated houses (`toyroom generate --rooms R --items K`), the brain with point "
        "beliefs: the exact model up to `ModelSettings.exact_max_worlds` worlds, the "
        "factored one above (`brain/model/factored.py`; the graded default uses it there too). "
        "`tv vs exact`: mean total-variation distance "
        "between the factored and exact item beliefs per person, item and tick, where the exact "
        "model fits. `graded`: the default (graded beliefs: exact up to 512 worlds, "
        "`brain/model/person/gradedfactored.py` above), its step and its TV against the exact graded model.",
        "",
        "| rooms | items | worlds | model | planner s | step us (p99) | exact: planner s, step us "
        "| tv vs exact | preference tv | graded step us (p99) | graded tv vs exact |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    lines += _scaling_rows(numbers)
    lines += _household_rows(numbers)
    lines += _embodied_rows(numbers)
    paper = numbers["paper_tv_vs_exact"]
    lines += [
        "",
        "Factored against exact on the paper map's scenarios (target: `tv_vs_exact` <= 0.05): "
        + ", ".join(
            f"{name} {v['tv_vs_exact']:.4f} (preferences {v['preference_tv_vs_exact']:.4f})"
            for name, v in paper.items()
        )
        + "; graded factored against exact graded: "
        + ", ".join(
            f"{name} {v['graded_tv_vs_exact']:.4f} (preferences {v['graded_preference_tv_vs_exact']:.4f})"
            for name, v in paper.items()
            if "graded_tv_vs_exact" in v
        )
        + "; smoothed, factored against exact forward-backward (point, graded): "
        + ", ".join(
            f"{name} {v['smoothed_tv_vs_exact']:.4f}, {v['graded_smoothed_tv_vs_exact']:.4f} "
            f"(preferences {v['smoothed_preference_tv_vs_exact']:.4f}, "
            f"{v['graded_smoothed_preference_tv_vs_exact']:.4f})"
            for name, v in paper.items()
            if "smoothed_tv_vs_exact" in v
        )
        + ".",
        "",
        f"![step and planner time against the number of worlds]({figure})",
    ]
    return "\n".join(lines) + "\n"


def write(bench_json: Path, readme: Path | None = None, figure: Path | None = None) -> Path:
    """Write ``perf.md`` and ``scaling.png`` next to ``bench_json`` (and into the README)."""
    numbers = json.loads(bench_json.read_text())
    out = bench_json.parent
    plot(numbers, out / "scaling.png")
    command = "toyroom bench --quick" if numbers.get("quick") else "toyroom bench"
    (out / "perf.md").write_text(markdown(numbers, "scaling.png", command))
    if readme is not None:
        target = figure or readme.parent / "docs" / "perf" / "scaling.png"
        target.parent.mkdir(parents=True, exist_ok=True)
        shutil.copyfile(out / "scaling.png", target)
        text = readme.read_text()
        if START not in text or END not in text:
            raise SystemExit(f"{readme} has no '{START}' ... '{END}' block to replace")
        head, rest = text.split(START, 1)
        _, tail = rest.split(END, 1)
        section = markdown(numbers, target.relative_to(readme.parent).as_posix(), command)
        readme.write_text(f"{head}{START}\n{section}{END}{tail}")
    return out / "perf.md"


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("bench_json", type=Path)
    parser.add_argument("--readme", type=Path)
    parser.add_argument("--figure", type=Path)
    args = parser.parse_args()
    print(f"wrote {write(args.bench_json, args.readme, args.figure)}")
