"""Helpers shared by the tests (importable as ``support``)."""

from __future__ import annotations

import importlib.util
import socket
import subprocess
import sys
from pathlib import Path
from types import ModuleType
from typing import Any

from protocol import BY_TAG, CommandStatus, Message, RobotCommand, decode
from protocol.examples import example_paths


def free_port() -> int:
    """A TCP port on 127.0.0.1 that nothing listens on right now."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as sock:
        sock.bind(("127.0.0.1", 0))
        return int(sock.getsockname()[1])


def golden_examples() -> dict[str, Message]:
    """Every golden example, decoded, keyed by message type."""
    return {tag: decode(path.read_bytes(), BY_TAG[tag]) for tag, path in example_paths().items()}


class EngineProcess:
    """``python -m sim2d`` as a real process on a world; a context manager that kills it.
    Its output goes to a temporary file (a pipe nobody reads would block a chatty engine),
    which :meth:`output` reads."""

    def __init__(self, world: str, *args: str) -> None:
        import sys

        self.world = world
        self._start([sys.executable, "-m", "sim2d", "--world", world, "--log-level", "WARNING", *args])

    def _start(self, command: list[str]) -> None:
        import subprocess
        import tempfile

        self.log = tempfile.TemporaryFile()
        self.process = subprocess.Popen(command, stdout=self.log, stderr=subprocess.STDOUT)

    def output(self) -> str:
        """Everything the engine has printed so far."""
        self.log.seek(0)
        return self.log.read().decode(errors="replace")

    def __enter__(self) -> EngineProcess:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    def close(self) -> None:
        if self.process.poll() is None:
            self.process.terminate()
            try:
                self.process.wait(timeout=10)
            except Exception:
                self.process.kill()
                self.process.wait(timeout=10)
        self.log.close()


class BrainProcess(EngineProcess):
    """``python -m brain`` as a real process on a world (logs at WARNING), its output in a
    temporary file (:meth:`output`); a context manager that kills it."""

    def __init__(self, world: str, *args: str) -> None:
        self.world = world
        self._start([sys.executable, "-m", "brain", "--world", world, "--log-level", "WARNING", *args])

    def finish(self, timeout: float) -> int:
        """The brain's exit status, failing the test if it runs past ``timeout`` seconds."""
        import pytest

        try:
            return self.process.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            pytest.fail(f"the brain did not exit within {timeout} s:\n{self.output()}")


def pause(process: subprocess.Popen[bytes], seconds: float) -> None:
    """Stop ``process`` (SIGSTOP) for ``seconds``, counted from when it is really stopped (a
    signal is delivered when the process is next scheduled), then continue it (SIGCONT): an
    editor's breakpoint, held ``seconds``."""
    import signal
    import time

    import psutil

    process.send_signal(signal.SIGSTOP)
    try:
        stopped = psutil.Process(process.pid)
        deadline = time.monotonic() + 10
        while stopped.status() != psutil.STATUS_STOPPED:
            assert time.monotonic() < deadline, f"pid {process.pid} never stopped: {stopped.status()}"
            time.sleep(0.01)
        time.sleep(seconds)  # the fault itself
    finally:
        process.send_signal(signal.SIGCONT)


def handled(run_log: Path) -> list[dict[str, Any]]:
    """The states and events a brain handled, in order, from its ``--run-log`` folder
    (``inputs.jsonl``), without the engine's handshakes and without episode numbers (an engine
    reset by several brains in turn counts its episodes on): what two runs of one scenario
    must share when both followed the episode to its end."""
    import json

    records = [json.loads(line) for line in (run_log / "inputs.jsonl").read_text().splitlines()]
    return [{k: v for k, v in r.items() if k != "episode"} for r in records if r.get("type") != "engine_info"]


def run_brain(world: str, *args: str, timeout: float = 240) -> subprocess.CompletedProcess[str]:
    """``python -m brain`` on ``world`` as a real process, to its end (logs at WARNING)."""
    return subprocess.run(
        [sys.executable, "-m", "brain", "--world", world, "--log-level", "WARNING", *args],
        capture_output=True,
        text=True,
        timeout=timeout,
    )


def toyroom_run(out: Path, scenario: str, *extra: str) -> Path:
    """``toyroom run`` as a real process (engine and brain processes over loopback Zenoh);
    returns the results directory."""
    import subprocess
    import sys

    result = subprocess.run(
        # a loaded machine may take seconds to answer one request: wait up to 60 s (a request
        # answered sooner takes no longer; a test's own --timeout, later, overrides this one)
        [
            sys.executable,
            "-m",
            "toyroom",
            "run",
            "--scenario",
            scenario,
            "--out",
            str(out),
            "--timeout",
            "60",
            *extra,
        ],
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert result.returncode == 0, f"toyroom run {scenario} failed:\n{result.stdout}\n{result.stderr}"
    return out


def toyroom_fit(*args: str | Path) -> subprocess.CompletedProcess[str]:
    """``toyroom fit ARGS --no-progress`` as a real process."""
    return subprocess.run(
        [sys.executable, "-m", "toyroom", "fit", *map(str, args), "--no-progress"],
        capture_output=True,
        text=True,
        timeout=600,
    )


class MindCsv:
    """``mind.csv`` indexed for assertions: ``at(agent, label)`` and ``p(...)``."""

    def __init__(self, path: Path) -> None:
        import csv

        self.path = path
        with path.open(newline="") as handle:
            self.rows = list(csv.DictReader(handle))
        self.label_tick = {(r["agent"], r["label"]): int(r["tick"]) for r in self.rows if r["label"]}
        self.index = {
            (int(r["tick"]), r["agent"], r["quantity"], r["item"], r["value"]): r for r in self.rows
        }

    def tick(self, agent: str, label: str) -> int:
        assert (agent, label) in self.label_tick, (
            f"no step '{label}' of {agent}; labels: {sorted(self.label_tick)}"
        )
        return self.label_tick[(agent, label)]

    def belief(self, agent: str, tick: int, item: str, locations: str, column: str = "p_smoothed") -> float:
        """Probability mass of ``item`` over the ``+``-separated ``locations`` at ``tick``."""
        return sum(
            float(self.index[(tick, agent, "belief", item, loc)][column]) for loc in locations.split("+")
        )

    def preference(self, agent: str, tick: int, item: str, column: str = "p_smoothed") -> float:
        return float(self.index[(tick, agent, "preference", item, "")][column])

    def nested(
        self, agent: str, tick: int, other: str, item: str, location: str, column: str = "p_online"
    ) -> float:
        """P(``agent`` believes ``other`` believes ``item`` is at ``location``) at ``tick``."""
        return float(self.index[(tick, agent, "nested_belief", item, f"{other}:{location}")][column])

    def false_belief(self, agent: str, tick: int, item: str, column: str = "p_online") -> float:
        """P(the agent's belief gives ``item``'s true location too little mass) at ``tick``."""
        return float(self.index[(tick, agent, "false_belief", item, "")][column])


class EventsCsv:
    """``events.csv`` of a run, for assertions."""

    def __init__(self, path: Path) -> None:
        import csv

        with path.open(newline="") as handle:
            self.rows = list(csv.DictReader(handle))

    def find(self, **want: str) -> list[dict[str, str]]:
        """Rows whose columns equal ``want`` (``detail__startswith`` for a prefix)."""
        out = []
        for row in self.rows:
            ok = True
            for key, value in want.items():
                if key.endswith("__startswith"):
                    ok = ok and row[key.removesuffix("__startswith")].startswith(value)
                elif key.endswith("__contains"):
                    ok = ok and value in row[key.removesuffix("__contains")]
                else:
                    ok = ok and row[key] == value
            if ok:
                out.append(row)
        return out

    def first_tick(self, **want: str) -> int:
        rows = self.find(**want)
        assert rows, f"no event with {want}"
        return int(rows[0]["tick"])


class GridEngineProcess(EngineProcess):
    """The example grid engine (``examples/grid_engine/main.py``) as a real process."""

    def __init__(self, world: str, *args: str) -> None:
        import sys

        script = Path(__file__).resolve().parents[1] / "examples" / "grid_engine" / "main.py"
        self.world = world
        self._start([sys.executable, str(script), "--world", world, *args])


class GatewayProcess(EngineProcess):
    """``python -m toyroom.gateway`` on a world, on a free loopback port (:attr:`url`)."""

    def __init__(self, world: str, *args: str) -> None:
        import sys
        import time

        from toyroom.gateway import GATEWAY_READY

        self.world = world
        self._start(
            [sys.executable, "-m", "toyroom.gateway", "--world", world, "--listen", "ws://127.0.0.1:0", *args]
        )
        deadline = time.monotonic() + 30
        while (match := GATEWAY_READY.search(self.output())) is None:
            assert self.process.poll() is None and time.monotonic() < deadline, (
                f"the gateway did not start:\n{self.output()}"
            )
            time.sleep(0.05)
        self.url = match.group("url")


class CSharpEngineProcess(EngineProcess):
    """The C# SDK's grid engine under Mono (built when stale), on the gateway at ``url``,
    with scenario ``scenario`` exported into ``folder``."""

    def __init__(self, url: str, folder: Path, scenario: str, *args: str) -> None:
        from toyroom.gateway import csharp

        csharp.export_scenario(scenario, folder)
        self._start(csharp.engine_command(url, folder, "--scenario", scenario, *args))


class GodotEngineProcess(EngineProcess):
    """The Godot add-on's sample under ``godot3-server`` (clients/godot/), on the gateway at
    ``url``, with scenario ``scenario`` exported into ``folder``."""

    def __init__(self, url: str, folder: Path, scenario: str, *args: str) -> None:
        from toyroom.gateway import godot

        godot.export_scenario(scenario, folder)
        self._start(godot.engine_command(url, folder, "--scenario", scenario, *args))


STUDIES = Path(__file__).resolve().parents[1] / "studies"


def study(name: str) -> ModuleType:
    """``studies/NAME.py`` imported as the module ``NAME`` (a script, not a package; it is
    registered in ``sys.modules`` first, as its dataclasses look their module up)."""
    if name not in sys.modules:
        spec = importlib.util.spec_from_file_location(name, STUDIES / f"{name}.py")
        assert spec is not None and spec.loader is not None, f"no study {STUDIES / name}.py"
        module = importlib.util.module_from_spec(spec)
        sys.modules[name] = module
        spec.loader.exec_module(module)
    return sys.modules[name]


class RunProcess:
    """``toyroom run --no-live ARGS`` as a real process, its output in a temporary file: what
    the fault tests stop, stall and kill (its nodes by name) and wait for."""

    def __init__(self, *args: str) -> None:
        import subprocess
        import sys
        import tempfile

        self.log = tempfile.TemporaryFile()
        command = [sys.executable, "-m", "toyroom", "run", "--no-live", *args]
        self.process = subprocess.Popen(command, stdout=self.log, stderr=subprocess.STDOUT)

    def output(self) -> str:
        """Everything the run has printed so far."""
        self.log.seek(0)
        return self.log.read().decode(errors="replace")

    def nodes(self) -> dict:
        """The run's engine and brain processes (``psutil.Process``), by name."""
        import psutil

        found = {}
        for process in psutil.Process(self.process.pid).children(recursive=True):
            try:
                line = process.cmdline()
            except psutil.NoSuchProcess:
                continue
            for name, package in (("engine", "sim2d"), ("brain", "brain")):
                if package in line and "-m" in line and "check-settings" not in line:
                    found[name] = process
        return found

    def finish(self, timeout: float = 120) -> int:
        """The run's exit status, failing the test if it runs past ``timeout`` seconds."""
        import subprocess

        import pytest

        try:
            return self.process.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            pytest.fail(f"toyroom run did not exit within {timeout} s:\n{self.output()}")

    def close(self) -> None:
        """Kill the run and its nodes if they are still there."""
        import psutil

        if self.process.poll() is None:
            for child in psutil.Process(self.process.pid).children(recursive=True):
                child.kill()
            self.process.kill()
            self.process.wait()
        self.log.close()


def long_paper_2(folder: Path, ticks: int, name: str) -> Path:
    """paper-2 whose first step (A1 playing) lasts ``ticks`` ticks, written with its map into
    ``folder`` as ``NAME.toml``: a run of the length a fault test needs."""
    scenarios = Path(__file__).resolve().parents[1] / "sim2d" / "scenarios"
    (folder / "paper.map.toml").write_text((scenarios / "paper.map.toml").read_text())
    text = (scenarios / "paper-2.toml").read_text()
    first = '{ do = "play", ticks = 20, label = "0" }'
    assert first in text, "paper-2's first step changed: update tests/support.py long_paper_2"
    (folder / f"{name}.toml").write_text(text.replace(first, first.replace("ticks = 20", f"ticks = {ticks}")))
    return folder / f"{name}.toml"


_command_ids = iter(range(1_000_000))


def run_command(
    engine: Any, action: object, tracker: Any = None, max_ticks: int = 2000
) -> list[CommandStatus]:
    """Send one robot command to a sim2d ``engine`` (in-process) and step until it ends,
    ``tracker`` (a :class:`brain.tracking.tracker.MindTracker`, if any) observing every tick;
    every status the command got, in order.

    Raises:
        AssertionError: the command did not end within ``max_ticks``.
    """
    command = RobotCommand(id=f"c{next(_command_ids)}", robot="robot", action=action)  # type: ignore[arg-type]
    statuses = [s for s in engine.command(command) if s.command == command.id]
    for _ in range(max_ticks):
        if statuses and statuses[-1].state.final:
            return statuses
        result = engine.step()
        if tracker is not None:
            tracker.observe(result.state, result.events)
        statuses += [s for s in result.statuses if s.command == command.id]
    raise AssertionError(f"{action} never ended in {max_ticks} ticks: {statuses}")


ONE_PERSON = """
name = "{name}"
map = "{map}"
robot = "act"
max_ticks = 2000

[[items]]
id = "ball"
shape = "ball"
at = "S1"

[[items]]
id = "skate"
shape = "board"
at = "P2"

[[agents]]
id = "A1"
kind = "person"
home = {a1}
wants = "skate"
script = [{{ do = "wait" }}]

[[agents]]
id = "robot"
kind = "robot"
home = {robot}
"""


def one_person(folder: Path, name: str, a1: tuple[int, int], robot: tuple[int, int]) -> Path:
    """Write a paper-map scenario ``name`` into ``folder``: the ball at S1, the skate at P2, A1
    (who wants the skate) waiting at cell ``a1`` and an acting robot at ``robot``; its path."""
    from sim2d.scenario.maps import SCENARIO_DIR

    path = folder / f"{name}.toml"
    paper = (SCENARIO_DIR / "paper.map.toml").as_posix()
    path.write_text(ONE_PERSON.format(name=name, map=paper, a1=list(a1), robot=list(robot)))
    return path
