# `make run` and `make test` each create .venv when it is missing and install the project
# into it (with the test and ray extras for `make test`), then run the main job / the test suite.
PYTHON ?= python3
VENV ?= .venv
PY := $(VENV)/bin/python

.PHONY: run test schema clean

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

test: $(VENV)/.test-installed
	$(PY) -m pytest

schema: $(VENV)/.run-installed
	$(VENV)/bin/toyroom schema

clean:
	rm -rf $(VENV) build *.egg-info .pytest_cache .hypothesis
