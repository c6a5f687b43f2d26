"""Where an evaluation episode's CPU goes: the runs of ``toyroom eval`` (the robot observing,
with the shadow observers, then acting with ``tom``) on one episode per map, each with the
CPU seconds of its engine process, its brain process and the evaluator (this process, less
this script's own sampling), read from ``/proc`` (Linux only).

A node's CPU is its last sample before it exits, taken every 20 ms, so it may miss up to that
much. With ``toyroom eval``'s two workers on a 2-core machine, the wall seconds per episode can
be no lower than about half the episode's CPU seconds printed here.

    python studies/split_eval_cpu.py [--seed 1] [--episodes 3]
"""

from __future__ import annotations

import argparse
import os
import tempfile
import threading
import time
from pathlib import Path

from rich.console import Console
from rich.table import Table

from toyroom.evaluation.episodes import cpu_seconds, episode_runs
from toyroom.evaluation.generation import generate, map_of
from toyroom.evaluation.runs import run_once

TICK_SECONDS = 1.0 / os.sysconf("SC_CLK_TCK")
NODES = {"-m brain": "brain", "-m sim2d": "engine"}


def _children() -> dict[int, tuple[str, float]]:
    """This process's node children: pid -> (node, CPU seconds so far)."""
    out = {}
    me = os.getpid()
    for entry in os.listdir("/proc"):
        if not entry.isdigit():
            continue
        try:
            stat = Path(f"/proc/{entry}/stat").read_text()
            fields = stat[stat.rindex(")") + 2 :].split()  # after "pid (comm) "
            if int(fields[1]) != me:
                continue
            command = Path(f"/proc/{entry}/cmdline").read_bytes().replace(b"\0", b" ").decode()
        except (OSError, ValueError):
            continue
        node = next((name for flag, name in NODES.items() if flag in command), None)
        if node is not None:
            out[int(entry)] = (node, (int(fields[11]) + int(fields[12])) * TICK_SECONDS)
    return out


class Sampler:
    """Samples the node children's CPU until stopped; keeps each one's last sample and its
    own CPU time (to take off the evaluator's)."""

    def __init__(self, every: float = 0.02) -> None:
        self.last: dict[int, tuple[str, float]] = {}
        self.own = 0.0
        self._every = every
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._thread.start()

    def _run(self) -> None:
        while not self._stop.wait(self._every):
            self.last.update(_children())
        self.own = time.thread_time()

    def stop(self) -> dict[str, float]:
        self._stop.set()
        self._thread.join()
        totals: dict[str, float] = {}
        for node, seconds in self.last.values():
            totals[node] = totals.get(node, 0.0) + seconds
        return totals


def main(seed: int, episodes: int) -> list[dict[str, float | str]]:
    rows: list[dict[str, float | str]] = []
    with tempfile.TemporaryDirectory(prefix="toyroom-evalcpu-") as folder:
        work = Path(folder)
        values = ("--values-cache", str(work / "values"))
        for index in range(episodes):
            scenario = generate(work / "scenarios", index, seed)
            for spec in episode_runs(scenario, values):
                sampler, cpu, started = Sampler(), cpu_seconds()["evaluator"], time.monotonic()
                run_once(spec, work)
                wall, evaluator = time.monotonic() - started, cpu_seconds()["evaluator"] - cpu
                nodes = sampler.stop()
                rows.append(
                    {
                        "map": map_of(index),
                        "run": spec.tag.removeprefix(f"{scenario.stem}-"),
                        "wall_s": wall,
                        "engine_cpu_s": nodes.get("engine", 0.0),
                        "brain_cpu_s": nodes.get("brain", 0.0),
                        "evaluator_cpu_s": max(evaluator - sampler.own, 0.0),
                    }
                )
    return rows


def show(rows: list[dict[str, float | str]], episodes: int) -> None:
    table = Table(title="CPU seconds of each run of toyroom eval (one episode per map)")
    for column in ("map", "run", "wall s", "engine", "brain", "evaluator", "all"):
        table.add_column(column, justify="left" if column in ("map", "run") else "right", no_wrap=True)
    keys = ("engine_cpu_s", "brain_cpu_s", "evaluator_cpu_s")
    for row in rows:
        numbers = [float(row[k]) for k in keys]
        table.add_row(
            str(row["map"]),
            str(row["run"]),
            f"{float(row['wall_s']):.2f}",
            *(f"{n:.2f}" for n in numbers),
            f"{sum(numbers):.2f}",
        )
    sums = [sum(float(r[k]) for r in rows) for k in keys]
    everything = sum(sums)
    table.add_row(
        "per episode",
        "",
        f"{sum(float(r['wall_s']) for r in rows) / episodes:.2f}",
        *(f"{s / episodes:.2f} ({s / everything:.0%})" for s in sums),
        f"{everything / episodes:.2f}",
    )
    Console().print(table)


if __name__ == "__main__":
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--episodes", type=int, default=3, help="one per map, cycling (default 3)")
    args = parser.parse_args()
    show(main(args.seed, args.episodes), args.episodes)
