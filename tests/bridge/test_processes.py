"""Node processes start with single-threaded BLAS unless the user chose otherwise."""

from __future__ import annotations

import sys

from bridge.processes import BLAS_THREADS, start_node

PRINT_ENV = f"import os; print(' '.join(os.environ.get(n, '-') for n in {BLAS_THREADS!r}))"


def run_and_read(tmp_path, monkeypatch, **env: str) -> str:
    for name in BLAS_THREADS:
        monkeypatch.delenv(name, raising=False)
    for name, value in env.items():
        monkeypatch.setenv(name, value)
    log = tmp_path / "node.log"
    process = start_node([sys.executable, "-c", PRINT_ENV], log)
    assert process.wait(timeout=30) == 0, log.read_text()
    return log.read_text().strip()


def test_a_node_gets_one_blas_thread(tmp_path, monkeypatch):
    got = run_and_read(tmp_path, monkeypatch)
    assert got == "1 1 1", f"expected every BLAS thread count set to 1, got {got!r}"


def test_a_users_blas_threads_are_kept(tmp_path, monkeypatch):
    got = run_and_read(tmp_path, monkeypatch, OPENBLAS_NUM_THREADS="4")
    assert got == "4 1 1", f"expected the user's OPENBLAS_NUM_THREADS=4 kept, got {got!r}"
