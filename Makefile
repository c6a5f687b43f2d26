# `make run` and `make test` each create .venv when it is missing and install the project
# into it (with the test and ray extras for `make test`), then run the main job / the test suite.
PYTHON ?= python3
VENV ?= .venv
PY := $(VENV)/bin/python

.PHONY: run test schema clean chromium

$(VENV)/bin/python:
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip

$(VENV)/.run-installed: pyproject.toml | $(VENV)/bin/python
	$(PY) -m pip install --quiet -e .
	touch $@

$(VENV)/.test-installed: pyproject.toml | $(VENV)/bin/python
	$(PY) -m pip install --quiet -e ".[test,ray]"
	touch $@ $(VENV)/.run-installed

run: $(VENV)/.run-installed
	$(VENV)/bin/toyroom run --out out

test: $(VENV)/.test-installed chromium
	$(PY) -m pytest

# The viewer's tests render in Debian's headless Chromium; install it when missing (as root).
chromium:
	@command -v chromium >/dev/null 2>&1 || { apt-get update -qq && apt-get install -y -qq chromium >/dev/null; }

schema: $(VENV)/.run-installed
	$(VENV)/bin/toyroom schema

clean:
	rm -rf $(VENV) build *.egg-info .pytest_cache .hypothesis
