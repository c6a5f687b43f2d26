"""``toyroom bench``'s table on the console: each number of ``bench.json`` beside its target
(microseconds, milliseconds or seconds, as each row says)."""

from __future__ import annotations

from typing import Any

from rich.console import Console
from rich.table import Table

from .perfreport import EMBODIED_FIGURES, REVIEW_ENGINE_STEP_US


def show(numbers: dict[str, Any]) -> None:
    """Print the table of ``numbers`` (a ``bench.json``)."""
    quick = " --quick" if numbers["quick"] else ""
    table = Table(title=f"toyroom bench{quick} (state payload {numbers['payload_bytes']} bytes)")
    table.add_column("measure")
    table.add_column("value", justify="right")
    table.add_column("target", justify="right")
    rows = (*_transport_rows(numbers), *_gateway_rows(numbers["gateway"]), *_brain_rows(numbers))
    for row in (*rows, *_embodied_rows(numbers.get("households_embodied"))):
        table.add_row(*row)
    Console().print(table)


def _transport_rows(numbers: dict[str, Any]) -> list[tuple[str, str, str]]:
    """Zenoh, the bridge, the lock-step tick and what it is made of, presence."""
    profile = numbers["lockstep_profile"]
    mixed = profile["interleaved"]
    gone = numbers["presence_gone_ms"]
    low, high = REVIEW_ENGINE_STEP_US
    rows = [
        ("zenoh_rtt_us (raw, median)", f"{numbers['zenoh_rtt_us']:.0f}", ""),
        ("bridge_rtt_us (typed, median)", f"{numbers['bridge_rtt_us']:.0f}", ""),
        (
            "lockstep_tick_us (median)",
            f"{numbers['lockstep_tick_us']:.0f}",
            f"<= 1.5 x raw query: {mixed['ratio']:.2f} x [{mixed['ratio_lo']:.2f}, {mixed['ratio_hi']:.2f}]",
        ),
        ("lockstep_ticks_per_s", f"{numbers['lockstep_ticks_per_s']:.0f}", ""),
        (
            "presence_gone_ms (closed peer, median / max)",
            f"{gone['median']:.0f} / {gone['max']:.0f}",
            "< 1000",
        ),
        ("  raw ping-pong, two processes", f"{profile['zenoh_rtt_two_processes_us']:.0f}", ""),
        ("  raw query, two processes (interleaved)", f"{profile['zenoh_query_two_processes_us']:.0f}", ""),
        (
            "  typed query, fixed state, no engine (interleaved)",
            f"{profile['typed_query_us']:.0f}",
            f"{mixed['typed_query_ratio']:.2f} x raw [{mixed['typed_query_ratio_lo']:.2f}, "
            f"{mixed['typed_query_ratio_hi']:.2f}]",
        ),
        ("  engine tick alone (paper-auto)", f"{profile['engine_step_us']:.0f}", f"half of {low}-{high}"),
    ]
    then = profile["engine_step_vs_review"]
    if then is not None:
        rows.append(
            (
                f"  the same against {then['commit']} (interleaved, CPU time)",
                f"{then['now_us']:.0f} / {then['then_us']:.0f}",
                f"<= 0.5 x: {then['ratio']:.2f} x",
            )
        )
    return rows


def _gateway_rows(gateway: dict[str, Any]) -> list[tuple[str, str, str]]:
    """The gateway's query, and the grid engines' ticks where they were measured."""
    rows = [("gateway: query answered over WebSocket", f"{gateway['query_rtt_us']:.0f}", "")]
    ticks = gateway["lockstep_tick_us"]
    if "direct" in ticks:
        rows += [
            ("grid engine tick, Zenoh", f"{ticks['direct']:.0f}", ""),
            (
                "grid engine tick, through the gateway",
                f"{ticks['gateway']:.0f}",
                f"<= {2 * ticks['direct']:.0f} (2 x)",
            ),
        ]
    if "csharp" in ticks:
        rows.append(("C# grid engine tick (Mono), gateway", f"{ticks['csharp']:.0f}", ""))
    return rows


def _brain_rows(numbers: dict[str, Any]) -> list[tuple[str, str, str]]:
    """The evaluation's speed, and the brain's step and planner, point and graded."""
    evaluation = numbers["eval_timing"]
    step, graded = numbers["brain_step_us"], numbers["graded"]
    return [
        (
            f"eval_seconds_per_episode ({evaluation['episodes']} episodes, {evaluation['workers']} workers)",
            f"{evaluation['seconds_per_episode']:.2f}",
            "<= 1.2 (500 in 10 min)",
        ),
        ("point beliefs: brain_step_us median / p99", f"{step['median']:.0f} / {step['p99']:.0f}", "<= 1000"),
        ("point beliefs: planner_cold_s", f"{numbers['planner_cold_s']:.3f}", "<= 0.5"),
        (
            "graded beliefs (the default): brain_step_us median / p99",
            f"{graded['brain_step_us']['median']:.0f} / {graded['brain_step_us']['p99']:.0f}",
            "<= 1000",
        ),
        ("graded beliefs (the default): planner_cold_s", f"{graded['planner_cold_s']:.3f}", "<= 2"),
    ]


def _embodied_rows(row: dict[str, Any] | None) -> list[tuple[str, str, str]]:
    """The households' embodied row (:mod:`.embodied`), embodied beside omniscient (none in a
    ``bench.json`` from before it)."""
    if row is None:
        return []
    head = f"households, {row['rooms']} rooms, {row['items']} items, {row['people']} people"
    out = [(f"{head}, miss {row['miss']:g} ({row['ticks']} ticks): embodied (omniscient)", "", "")]
    for name, key, form in EMBODIED_FIGURES:
        value = f"{row['embodied'][key]:{form}} ({row['omniscient'][key]:{form}})"
        out.append((f"  {name}", value, f"<= {row['targets'][key]:g}"))
    return out
