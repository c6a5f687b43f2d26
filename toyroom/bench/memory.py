"""The brain's peak resident memory with lapses and an embodied robot (issue 53):
``toyroom bench --memory`` runs ``toyroom run`` on generated task episodes of ``house-a`` and
``house-b`` (rich minds) with ``miss = 0.2`` and ``perception = embodied``, and prints the
peak resident set size of the run's largest process (the brain), against the budget the
brain checks at start (:data:`brain.model.size.MEMORY_BUDGET_GB`).

Each run is measured in a fresh interpreter that starts ``toyroom run`` and reads
``getrusage(RUSAGE_CHILDREN).ru_maxrss`` once it has ended: the largest resident set of any
process of the run (on Linux, in KiB), which is the brain's on these houses.
"""

from __future__ import annotations

import json
import subprocess
import sys
import tempfile
from dataclasses import dataclass
from pathlib import Path

from brain.model.size import MEMORY_BUDGET_GB
from protocol import EpisodeKind, EpisodeMap, EpisodeSpec, Minds, TaskKind
from sim2d.generation.episodes import write_episode

HOUSES = (EpisodeMap.HOUSE_A, EpisodeMap.HOUSE_B)
SEEDS = (2, 4, 7)
"""The episode seeds: with ``miss = 0.2``, embodied, the two heaviest house-b task episodes of
seeds 1-4 before issue 53's slim history (2.71 and 2.02 GiB then), and seed 7, the heaviest
of seeds 5-12 after it (0.56 GiB)."""
SETTINGS = ("miss=0.2", "perception=embodied")
TASKS = tuple(TaskKind)
TICKS = 1500
"""The episodes' length: the one the seeds above and the memory budget were measured on
(longer than an evaluation's :data:`protocol.MAX_TICKS`)."""
_PROBE = """
import resource, subprocess, sys
done = subprocess.run(sys.argv[1:], capture_output=True, text=True)
print(done.returncode, resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss)
sys.stderr.write(done.stdout[-2000:] + done.stderr[-2000:])
"""


@dataclass(frozen=True)
class MemoryRun:
    """One run's peak resident memory (GiB) and how the run ended (``code`` 0: it ran to its
    end; else ``message`` is the run's last line, which says why)."""

    house: str
    seed: int
    peak_gb: float
    code: int
    message: str


def measure(house: EpisodeMap, seed: int, folder: Path, max_ticks: int = TICKS) -> MemoryRun:
    """Run one generated task episode of ``house`` with :data:`SETTINGS`; its peak memory."""
    spec = EpisodeSpec(Minds.RICH, EpisodeKind.TASKS, max_ticks, TASKS)
    scenario = write_episode(folder / "episodes", house, seed, spec)
    sets = [arg for setting in SETTINGS for arg in ("--set", setting)]
    run = [
        sys.executable,
        "-m",
        "toyroom",
        "run",
        "--scenario",
        str(scenario),
        "--out",
        str(folder / f"{house}-{seed}"),
    ]
    done = subprocess.run(
        [sys.executable, "-c", _PROBE, *run, *sets, "--no-live", "--timeout", "60"],
        capture_output=True,
        text=True,
        check=False,
    )
    code, kib = (int(v) for v in done.stdout.split()[:2])
    said = [line.strip() for line in done.stderr.splitlines() if line.strip()]
    return MemoryRun(house, seed, kib / 2**20, code, said[-1] if code and said else "")


def main(out: Path, seeds: tuple[int, ...] = SEEDS) -> list[MemoryRun]:
    """Measure every house and seed; print a table and write ``out/memory.json``."""
    out.mkdir(parents=True, exist_ok=True)
    runs = []
    with tempfile.TemporaryDirectory() as tmp:
        for house in HOUSES:
            for seed in seeds:
                runs.append(measure(house, seed, Path(tmp)))
                r = runs[-1]
                end = "ran to its end" if r.code == 0 else f"exit {r.code}: {r.message}"
                print(f"{house} seed {seed}: peak resident {r.peak_gb:.2f} GiB ({end})", flush=True)
    print(f"budget: {MEMORY_BUDGET_GB:.1f} GiB per brain ({', '.join(SETTINGS)})")
    (out / "memory.json").write_text(json.dumps([r.__dict__ for r in runs], indent=2))
    return runs
