# Two commands on a fresh machine: `make run` and `make test`.
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
PIP    := $(PY) -m pip

.PHONY: run test lint unit bench clean

$(PY):
	$(PYTHON) -m venv $(VENV)
	$(PIP) install --upgrade pip

# Reinstall when the project's metadata changes.
# Byte-compile too: this environment may set PYTHONDONTWRITEBYTECODE, and without
# .pyc files every `cspace` run would recompile the package (as pip does for wheels).
$(VENV)/.stamp-install: pyproject.toml | $(PY)
	$(PIP) install -e .
	$(PY) -m compileall -q src cli
	touch $@

$(VENV)/.stamp-test: pyproject.toml $(VENV)/.stamp-install
	$(PIP) install -e '.[test]'
	touch $@

run: $(VENV)/.stamp-install
	$(VENV)/bin/cspace inspect robots/arm7.urdf

lint: $(VENV)/.stamp-test
	$(VENV)/bin/ruff check src cli tests bench
	$(VENV)/bin/ruff format --check src cli tests bench
	$(VENV)/bin/mypy --strict src/cspace cli

unit: $(VENV)/.stamp-test
	$(PY) -m pytest -q

test: lint unit

bench: $(VENV)/.stamp-install
	$(PY) -m compileall -q src cli
	$(PY) bench/bench_inspect.py
	$(PY) bench/bench_configurations.py

clean:
	rm -rf $(VENV) build *.egg-info src/*.egg-info
