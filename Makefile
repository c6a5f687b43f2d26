# `make run` and `make test` each create .venv when it is missing and install the project
# into it, every dependency at the version pinned in constraints.txt (the lock), then run the
# main job / the test suite; `make check` is the fast tier (lint, types, in-process tests).
# `make lock` refreshes the lock; `make test-latest` runs the suite against the newest
# releases instead, in .venv-latest; `make wheel-check` builds the wheel and runs it from a
# fresh venv outside the checkout (CI runs it after `make test`).
PYTHON ?= python3
VENV ?= .venv
PY := $(VENV)/bin/python
LOCK := constraints.txt
PIP_VERSION := 26.3
UV_VERSION := 0.13.9
LATEST := .venv-latest

.PHONY: run test sweeps check lock test-latest wheel-check schema clean chromium mono tesseract godot bytecode

$(VENV)/bin/python:
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet pip==$(PIP_VERSION)

$(VENV)/.run-installed: pyproject.toml $(LOCK) | $(VENV)/bin/python
	$(PY) -m pip install --quiet -c $(LOCK) -e .
	touch $@

$(VENV)/.test-installed: pyproject.toml $(LOCK) | $(VENV)/bin/python
	$(PY) -m pip install --quiet -c $(LOCK) -e ".[test,ray]"
	touch $@ $(VENV)/.run-installed

# The project's modules compiled to bytecode beside their sources (__pycache__, ignored by git),
# again for what changed: where PYTHONDONTWRITEBYTECODE is set, as on these machines, every
# process (each engine, brain and command a run or a test starts) would otherwise compile them
# from source at its start: about 0.5 CPU-s for the brain, the engine and the command line.
bytecode: | $(VENV)/bin/python
	@PYTHONDONTWRITEBYTECODE= $(PY) -m compileall -q -j 0 protocol bridge sim2d brain toyroom examples/grid_engine studies >/dev/null

run: $(VENV)/.run-installed bytecode
	$(VENV)/bin/toyroom run --out out

# Four workers (pytest-xdist) on this 2-core machine: most of the suite waits on engines,
# brains and browsers (subprocesses that have cores of their own to use): with three, the
# cores were busy 53% of the time (17.0 CPU-min in 16.0 min, at 3b46f2f); every test has its
# own world and port. The 30 slowest are listed at the end:
# the suite must stay under 12 minutes here.
test: $(VENV)/.test-installed bytecode chromium mono tesseract godot
	$(PY) -m pytest -n 4 --durations=30

# The sweeps: tests that run a benchmark or a study end to end (`toyroom bench --quick`, a
# parameter's recovery over a dozen episodes), minutes of CPU each; CI runs them after `make
# test` (tests/tiers.py, the `sweep` mark).
sweeps: $(VENV)/.test-installed bytecode chromium mono tesseract godot
	$(PY) -m pytest -n 2 --tier sweeps --durations=10

# The fast tier: lint, types and every test that starts no process, Zenoh session, browser or
# Ray (tests/tiers.py marks the others `process`, and fails one that starts something unmarked).
check: $(VENV)/.test-installed bytecode
	$(PY) -m ruff check .
	$(PY) -m mypy
	$(PY) -m pytest --tier check -q -n 2

# Re-resolve every dependency (and the test and ray extras) to its newest release, for any
# platform and Python >= 3.11, with uv (pinned here); commit the new constraints.txt.
lock: | $(VENV)/bin/python
	$(PY) -m pip install --quiet uv==$(UV_VERSION)
	$(VENV)/bin/uv pip compile pyproject.toml --extra test --extra ray --universal \
		--python-version 3.11 --upgrade --quiet --custom-compile-command "make lock" -o $(LOCK)

# The suite against the newest releases of everything (no lock), to find drift on purpose.
test-latest: chromium mono tesseract godot
	rm -rf $(LATEST)
	$(PYTHON) -m venv $(LATEST)
	$(LATEST)/bin/python -m pip install --quiet --upgrade pip
	$(LATEST)/bin/python -m pip install --quiet --upgrade --upgrade-strategy eager -e ".[test,ray]"
	$(LATEST)/bin/python .ci/lockdiff.py $(LOCK)
	$(LATEST)/bin/python -m pytest

wheel-check: $(VENV)/.run-installed
	.ci/wheel-check $(PY) $(LOCK)

# The viewer's tests render in Debian's headless Chromium; install it when missing (as root).
chromium:
	@command -v chromium >/dev/null 2>&1 || { apt-get update -qq && apt-get install -y -qq chromium >/dev/null; }

# The viewer's tests read its labels back from screenshots with Debian's tesseract OCR;
# install it when missing (as root).
tesseract:
	@command -v tesseract >/dev/null 2>&1 || { apt-get update -qq && apt-get install -y -qq tesseract-ocr >/dev/null; }

# The C# SDK's tests compile it with Mono's mcs against Debian's Newtonsoft.Json and run the
# sample engine under mono; install both when missing (as root).
mono:
	@{ command -v mcs >/dev/null 2>&1 && pkg-config --exists newtonsoft-json 2>/dev/null; } || { apt-get update -qq && apt-get install -y -qq mono-devel libnewtonsoft-json-cil-dev >/dev/null; }

# The Godot add-on's tests run its sample headless under Debian's Godot 3.2 server build
# (clients/godot/, tests/clients/test_godot.py); install it when missing (as root).
godot:
	@command -v godot3-server >/dev/null 2>&1 || { apt-get update -qq && apt-get install -y -qq godot3-server >/dev/null; }

schema: $(VENV)/.run-installed
	$(VENV)/bin/toyroom schema

clean:
	rm -rf $(VENV) $(LATEST) build dist *.egg-info .pytest_cache .hypothesis
