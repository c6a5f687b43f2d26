"""``toyroom eval`` and ``toyroom fit`` on a real two-node Ray cluster of ``ray start``
processes on this machine, loopback only: the episodes spread over both nodes (each runs its
engines and brains on its own loopback) and score what the local backend scores, episode by
episode; their logs and recordings come back to the driver's output folder; a fit over the
cluster finds what worker processes find. ``--address`` without ``--backend ray`` is refused.

Two nodes on one machine, on loopback: Ray (2.60) turns ``127.0.0.1`` into the address of the
machine's route out (``resolve_ip_for_localhost``) unless ``RAY_ENABLE_WINDOWS_OR_OSX_CLUSTER=0``,
and ``ray start --address`` refuses to start a second node under that setting. So the head is
``ray start`` under it, and the second node is ``ray start``'s own entry point with this
machine's node address pinned to ``127.0.0.1`` (:data:`LOOPBACK_RAY_START`); its processes
run under the setting too. A real cluster's nodes need neither (docs/deployment.md).

The tests on the cluster are sweeps (``make sweeps``, tests/tiers.py): starting the two nodes
takes a minute or more of this machine's two cores, and they are about three minutes in all.
"""

from __future__ import annotations

import ctypes
import json
import math
import os
import secrets
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
from collections.abc import Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import pytest
from support import toyroom_fit

from toyroom.bench.households import scores
from toyroom.cli.cli import main as toyroom
from toyroom.evaluation.raybackend import LOCAL_ONLY, cluster_address, on_loopback

CLUSTER = pytest.mark.sweep  # the tests on the two Ray nodes: `make sweeps` (tests/tiers.py)

RAY = Path(sys.executable).with_name("ray")
EPISODES, SEED, TICKS = 4, 3, 300
LOOPBACK_RAY_START = (
    "import sys; import ray._private.ray_constants as constants, ray._private.services as services; "
    "constants.ENABLE_RAY_CLUSTER = True; services.get_node_ip_address = lambda address=None: '127.0.0.1'; "
    "from ray.scripts.scripts import main; sys.argv[0] = 'ray'; sys.exit(main())"
)
"""``ray start``, on a machine whose node address is ``127.0.0.1`` (see the module docstring)."""
NODES = """
import json, sys, time
import ray
ray.init(address=sys.argv[1], log_to_driver=False)
deadline = time.monotonic() + 60
while len(alive := [n for n in ray.nodes() if n["Alive"]]) < 2 and time.monotonic() < deadline:
    time.sleep(0.2)
print(json.dumps([{"id": n["NodeID"], "ip": n["NodeManagerAddress"], "second": "second" in n["Resources"]}
                  for n in alive]))
"""
"""Prints the cluster's live nodes once there are two (or after a minute)."""
PER_RUN = ("seconds", "run_seconds", "failed_runs", "node")
"""What an episode's entry says about the machine it ran on, not about the brain."""


@dataclass
class Cluster:
    address: str
    env: dict[str, str]
    nodes: list[dict[str, Any]]
    processes: list[subprocess.Popen[bytes]]


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


def _die_with_parent() -> None:
    """In the child: killed when this test process dies, whatever the way (Linux)."""
    libc = ctypes.CDLL(None, use_errno=True)
    libc.prctl(1, signal.SIGKILL, 0, 0, 0)  # PR_SET_PDEATHSIG


def _start(command: list[str], env: dict[str, str], log: Path) -> subprocess.Popen[bytes]:
    """``ray start --block ...``, in a process group of its own, once its node runs."""
    with log.open("wb") as out:
        process = subprocess.Popen(
            command,
            env=env,
            stdout=out,
            stderr=subprocess.STDOUT,
            start_new_session=True,
            preexec_fn=_die_with_parent if sys.platform == "linux" else None,
        )
    deadline = time.monotonic() + 90
    while "Ray runtime started" not in log.read_text(errors="replace"):
        if process.poll() is not None or time.monotonic() > deadline:
            _stop(process)
            pytest.fail(f"{' '.join(command[:3])} did not start a node:\n{log.read_text()[-3000:]}")
        time.sleep(0.1)
    return process


def _stop(process: subprocess.Popen[bytes]) -> None:
    """Stop a node: its ``ray start`` and every process of its group (only this test's)."""
    for sig, grace in ((signal.SIGTERM, 15.0), (signal.SIGKILL, 10.0)):
        try:
            os.killpg(process.pid, sig)
        except ProcessLookupError:
            pass
        try:
            process.wait(timeout=grace)
        except subprocess.TimeoutExpired:
            continue
        if sig == signal.SIGTERM:  # what it left behind, if anything
            try:
                os.killpg(process.pid, signal.SIGKILL)
            except ProcessLookupError:
                pass
        return


@pytest.fixture(scope="module")
def cluster() -> Iterator[Cluster]:
    """A head node and a second node (resource ``second``), one CPU each, on loopback, with a
    token of their own, their files in a temporary folder; stopped and removed after."""
    pytest.importorskip("ray")
    if not RAY.exists():
        pytest.skip(f"no ray executable next to {sys.executable}")
    root = Path(tempfile.mkdtemp(prefix="trray-", dir="/tmp" if Path("/tmp").is_dir() else None))
    env = {k: v for k, v in os.environ.items() if not k.startswith("RAY_")}
    env |= {
        "RAY_USAGE_STATS_ENABLED": "0",
        "RAY_AUTH_MODE": "token",
        "RAY_AUTH_TOKEN": secrets.token_hex(32),
        LOCAL_ONLY: "0",
        "RAY_GRACEFUL_SHUTDOWN_DRAIN_TIMEOUT_S": "0",
    }
    address = f"127.0.0.1:{_free_port()}"
    common = [
        "--block",
        "--num-cpus=1",
        "--disable-usage-stats",
        "--min-worker-port=0",
        "--max-worker-port=0",
    ]
    common += ["--dashboard-agent-listen-port=0"]
    processes: list[subprocess.Popen[bytes]] = []
    try:
        head = [str(RAY), "start", "--head", "--node-ip-address=127.0.0.1", f"--port={address.split(':')[1]}"]
        head += ["--include-dashboard=false", f"--temp-dir={root / 'head'}", *common]
        processes.append(_start(head, env, root / "head.log"))
        second = [sys.executable, "-c", LOOPBACK_RAY_START, "start", f"--address={address}"]
        second += ['--resources={"second": 1}', f"--temp-dir={root / 'second'}", *common]
        processes.append(_start(second, env, root / "second.log"))
        listed = subprocess.run(
            [sys.executable, "-c", NODES, address], env=env, capture_output=True, text=True, timeout=120
        )
        assert listed.returncode == 0, listed.stderr[-3000:]
        nodes = json.loads(listed.stdout.strip().splitlines()[-1])
        assert len(nodes) == 2 and sorted(n["second"] for n in nodes) == [False, True], nodes
        yield Cluster(address, env, nodes, processes)
    finally:
        for process in reversed(processes):
            _stop(process)
        shutil.rmtree(root, ignore_errors=True)


def _eval(env: dict[str, str], out: Path, *options: str) -> None:
    command = [sys.executable, "-m", "toyroom", "eval", "--episodes", str(EPISODES), "--seed", str(SEED)]
    command += ["--max-ticks", str(TICKS), "--workers", "2", "--out", str(out), *options]
    result = subprocess.run(command, env=env, capture_output=True, text=True, timeout=600)
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]


@pytest.fixture(scope="module")
def evaluations(cluster: Cluster, tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, Path]:
    """The output folders of one sweep run locally and on the cluster (recording every run)."""
    local, ray = tmp_path_factory.mktemp("local"), tmp_path_factory.mktemp("cluster")
    _eval(cluster.env, local, "--backend", "local")
    _eval(cluster.env, ray, "--backend", "ray", "--address", cluster.address, "--record")
    return local, ray


def _episodes(out: Path) -> dict[str, list[dict[str, Any]]]:
    return json.loads((out / "episodes.json").read_text())


def _differences(a: Any, b: Any, at: str = "") -> list[str]:
    """Where two entries differ: floats only beyond rounding (a sum over a set of names, as
    ``belief_tv``'s, adds in the order of the process's string hashes), all else exactly."""
    if isinstance(a, dict) and isinstance(b, dict) and a.keys() == b.keys():
        return [d for k in a for d in _differences(a[k], b[k], f"{at}/{k}")]
    if isinstance(a, list) and isinstance(b, list) and len(a) == len(b):
        return [d for i, pair in enumerate(zip(a, b, strict=True)) for d in _differences(*pair, f"{at}[{i}]")]
    if isinstance(a, float) and isinstance(b, float):
        return [] if math.isclose(a, b, rel_tol=1e-9, abs_tol=1e-12) else [f"{at}: {a} != {b}"]
    return [] if a == b else [f"{at}: {a!r} != {b!r}"]


def _processes(cluster: Cluster) -> list[Any]:
    import psutil

    found = []
    for process in cluster.processes:
        with_children = psutil.Process(process.pid)
        found += [with_children, *with_children.children(recursive=True)]
    return found


@CLUSTER
def test_the_cluster_listens_on_loopback_only(cluster: Cluster) -> None:
    assert {node["ip"] for node in cluster.nodes} == {"127.0.0.1"}, cluster.nodes
    listening = []
    for process in _processes(cluster):
        try:
            connections = process.net_connections(kind="inet")
        except Exception:  # psutil.NoSuchProcess, AccessDenied: gone, or not ours to see
            continue
        listening += [(process.name(), c.laddr.ip) for c in connections if c.status == "LISTEN"]
    assert listening, "the cluster's processes listen somewhere"
    outside = [(name, ip) for name, ip in listening if ip not in ("127.0.0.1", "::ffff:127.0.0.1")]
    assert not outside, f"listening beyond loopback: {outside}"


@pytest.mark.timeout(600)
@CLUSTER
def test_episodes_spread_over_the_nodes_and_score_as_locally(
    evaluations: tuple[Path, Path], cluster: Cluster
) -> None:
    local, ray = evaluations
    here, there = _episodes(local), _episodes(ray)
    assert list(here) == list(there)
    ran_on = {episode["node"] for episodes in there.values() for episode in episodes}
    assert ran_on == {node["id"] for node in cluster.nodes}, (
        f"episodes ran on {ran_on}, nodes {cluster.nodes}"
    )
    for condition, episodes in here.items():
        assert len(episodes) == len(there[condition]) == EPISODES
        for mine, theirs in zip(episodes, there[condition], strict=True):
            assert "error" not in mine and "error" not in theirs, (mine, theirs)
            a, b = ({k: v for k, v in e.items() if k not in PER_RUN} for e in (mine, theirs))
            assert not _differences(a, b), f"episode {mine['index']}: {_differences(a, b)}"
    kept = [json.loads(line) for line in (ray / "episodes.jsonl").read_text().splitlines()]
    assert sorted(e["index"] for e in kept) == list(range(EPISODES)), "each entry kept as it arrived"


@CLUSTER
def test_the_driver_gets_the_logs_and_recordings(evaluations: tuple[Path, Path]) -> None:
    """What an episode made on its node is written by the driver into the output folder."""
    _, ray = evaluations
    recordings = sorted((ray / "recordings").rglob("*.mcap"))
    assert len(recordings) == 2 * EPISODES, recordings  # observing, and acting (tom)
    logs = list(ray.glob("toyroom-eval-*/*/logs/*.brain.log"))
    assert len(logs) == 2 * EPISODES, logs


@pytest.mark.timeout(600)
@CLUSTER
def test_fit_on_the_cluster_finds_what_worker_processes_find(
    evaluations: tuple[Path, Path], cluster: Cluster, tmp_path: Path
) -> None:
    _, ray = evaluations
    recordings = sorted((ray / "recordings").rglob("*-observe.mcap"))
    args = [*map(str, recordings), "--params", "beta", "--grid", "beta=0.5,2", "--models", "graded,motion"]
    args += ["--folds", "2", "--no-progress"]
    local, remote = (
        subprocess.run(
            [sys.executable, "-m", "toyroom", "fit", *args, *options, "--out", str(tmp_path / name)],
            env=cluster.env,  # its token
            capture_output=True,
            text=True,
            timeout=600,
        )
        for name, options in (("local", []), ("ray", ["--backend", "ray", "--address", cluster.address]))
    )
    assert local.returncode == 0 and remote.returncode == 0, local.stderr[-2000:] + remote.stderr[-2000:]
    a, b = (json.loads((tmp_path / d / "fit.json").read_text())["models"] for d in ("local", "ray"))
    for model in ("graded", "motion"):
        assert a[model]["held_out_per_action"] == b[model]["held_out_per_action"], (model, a[model], b[model])


HOUSEHOLDS = [
    *("--days", "2", "--episodes", "2", "--seed", str(SEED), "--kind", "tasks"),
    *("--max-ticks", "120", "--workers", "2", "--policies", "none"),
]
"""Two households of two days: four chain days each (observing with memory and without)."""


@pytest.mark.timeout(900)
@CLUSTER
def test_households_stopped_on_the_cluster_resume_there_to_the_local_metrics(
    cluster: Cluster, tmp_path: Path
) -> None:
    """Issue 67: a households evaluation on the two nodes, stopped by Ctrl-C once a chain day
    is kept and run again on the cluster, gives the uninterrupted local run's metrics."""
    local, ray = tmp_path / "local", tmp_path / "ray"
    base = [sys.executable, "-m", "toyroom", "eval", *HOUSEHOLDS]
    done = subprocess.run(
        [*base, "--out", str(local)], env=cluster.env, capture_output=True, text=True, timeout=600
    )
    assert done.returncode == 0, done.stderr[-3000:]
    on_ray = [*base, "--out", str(ray), "--backend", "ray", "--address", cluster.address]
    part = subprocess.Popen(
        on_ray, env=cluster.env, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True
    )
    try:
        kept = ray / "episodes.jsonl"
        deadline = time.monotonic() + 400
        while part.poll() is None and not _kept(kept) and time.monotonic() < deadline:
            time.sleep(0.05)  # polling for the event (a chain day appended)
        assert part.poll() is None, (
            f"the evaluation ended before a chain day was kept: {part.communicate()[1][-2000:]}"
        )
        part.send_signal(signal.SIGINT)
        _, stopped = part.communicate(timeout=120)
    finally:
        if part.poll() is None:
            part.kill()
            part.wait()
    assert part.returncode == 130, f"expected exit 130 on SIGINT, got {part.returncode}:\n{stopped[-2000:]}"
    again = subprocess.run(on_ray, env=cluster.env, capture_output=True, text=True, timeout=600)
    assert again.returncode == 0, again.stdout[-2000:] + again.stderr[-3000:]
    here, there = scores(local), scores(ray)
    differing = [
        f"{k}: {here.get(k)} != {there.get(k)}"
        for k in sorted(here.keys() | there.keys())
        if here.get(k) != there.get(k)
    ]
    assert not differing, "expected the local run's metrics, got:\n" + "\n".join(differing[:10])
    (records,) = _episodes(ray).values()
    assert {r.get("node") for r in records} <= {n["id"] for n in cluster.nodes} and all(
        r.get("node") for r in records
    ), f"expected each household day's node, got {[r.get('node') for r in records]}"


def _kept(jsonl: Path) -> bool:
    """Whether ``jsonl`` holds a finished chain day."""
    return jsonl.exists() and bool(jsonl.read_text().strip())


def test_address_needs_the_ray_backend(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert toyroom(["eval", "--address", "127.0.0.1:6379", "--out", str(tmp_path / "eval")]) == 2
    assert "--address" in capsys.readouterr().err and not (tmp_path / "eval").exists()
    trace = tmp_path / "trace.jsonl"
    trace.write_text("")
    fit = toyroom_fit(trace, "--address", "127.0.0.1:6379", "--out", tmp_path / "fit")
    assert fit.returncode == 2 and "--address" in fit.stderr and "--backend ray" in fit.stderr, fit.stderr


def test_an_address_where_no_cluster_answers_is_named(tmp_path: Path) -> None:
    """Ray would try to reach it for minutes; the command says so at once."""
    pytest.importorskip("ray")
    address = f"127.0.0.1:{_free_port()}"
    command = [sys.executable, "-m", "toyroom", "eval", "--episodes", "1", "--max-ticks", "100"]
    command += ["--backend", "ray", "--address", address, "--out", str(tmp_path)]
    result = subprocess.run(command, capture_output=True, text=True, timeout=120)
    assert result.returncode == 2 and f"no Ray cluster answers at {address}" in result.stderr, result.stderr


def test_the_address_defaults_to_ray_address(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setenv("RAY_ADDRESS", "10.0.0.5:6379")
    assert cluster_address("127.0.0.1:7000") == "127.0.0.1:7000"
    assert cluster_address(None) == "10.0.0.5:6379"
    monkeypatch.delenv("RAY_ADDRESS")
    assert cluster_address(None) is None
    assert on_loopback("127.0.0.1:6379") and on_loopback("localhost:6379")
    assert not on_loopback("10.0.0.5:6379") and not on_loopback("ray://127.0.0.1:10001")
