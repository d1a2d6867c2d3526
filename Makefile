# Two commands on a fresh machine: `make run` and `make test`.
PYTHON ?= python3
VENV   := .venv
PY     := $(VENV)/bin/python
PIP    := $(PY) -m pip

.PHONY: run test lint unit docs bench clean shells browser

# One recipe at a time (make -j too): `run` and `test` install into the same .venv.
.NOTPARALLEL:

$(PY):
	$(PYTHON) -m venv $(VENV)
	$(PIP) install --upgrade pip

# Reinstall when the project's metadata changes.
# Byte-compile too: this environment may set PYTHONDONTWRITEBYTECODE, and without
# .pyc files every `cspace` run would recompile the package (as pip does for wheels).
$(VENV)/.stamp-install: pyproject.toml | $(PY)
	$(PIP) install -e .
	$(PY) -m compileall -q src
	touch $@

# The test extra installs all that `pip install -e .` does: one resolve and one editable
# build for both (the install's stamp is touched with it).
$(VENV)/.stamp-test: pyproject.toml tests/robot-data.txt | $(PY)
	$(PIP) install -e '.[test]'
	$(PIP) install --no-deps -r tests/robot-data.txt
	$(PY) -m compileall -q src
	touch $(VENV)/.stamp-install $@

run: $(VENV)/.stamp-install
	$(VENV)/bin/cspace inspect robots/arm7.urdf

lint: $(VENV)/.stamp-test
	$(VENV)/bin/ruff check src tests bench conftest.py
	$(VENV)/bin/ruff format --check src tests bench conftest.py
	$(VENV)/bin/mypy --strict src/cspace

# zsh and fish, for the shell-completion tests (Debian's packages; bash is everywhere).
shells:
	@command -v zsh >/dev/null && command -v fish >/dev/null || \
	  apt-get install -y --no-install-recommends zsh fish >/dev/null 2>&1 || \
	  (apt-get update -qq >/dev/null 2>&1 && \
	   apt-get install -y --no-install-recommends zsh fish >/dev/null 2>&1) || \
	  echo "zsh and fish could not be installed (apt-get install zsh fish): their completion tests will fail"

# Chromium, for the HTML report's browser tests (Debian's package, driven by Playwright).
browser:
	@command -v chromium >/dev/null || \
	  apt-get install -y --no-install-recommends chromium >/dev/null 2>&1 || \
	  (apt-get update -qq >/dev/null 2>&1 && \
	   apt-get install -y --no-install-recommends chromium >/dev/null 2>&1) || \
	  echo "Chromium could not be installed (apt-get install chromium): the HTML report's browser tests will fail"

# One test file per worker at a time: a file's costly session fixtures are made once.
# Files in the order collected (tests/conftest.py puts the longest first), not reordered
# by their number of tests, so that both workers end together.
unit: $(VENV)/.stamp-test shells browser
	$(PY) -m pytest -q -n 2 --dist loadfile --no-loadscope-reorder

# The documentation site (docs/ and mkdocs.yml) into site/; strict: a broken link, a
# missing page or a docstring griffe cannot read fails.
docs: $(VENV)/.stamp-test
	NO_MKDOCS_2_WARNING=1 $(VENV)/bin/mkdocs build --strict --quiet

test: lint unit docs

bench: $(VENV)/.stamp-test
	$(PY) -m compileall -q src
	$(PY) bench/bench_inspect.py
	$(PY) bench/bench_configurations.py
	$(PY) bench/bench_conventions.py --threads 2
	$(PY) bench/bench_conventions.py --threads 1
	$(PY) bench/bench_commands.py
	$(PY) bench/bench_scaling.py
	$(PY) bench/bench_many.py
	$(PY) bench/bench_folders.py
	$(PY) bench/bench_collisions.py

clean:
	rm -rf $(VENV) build site *.egg-info src/*.egg-info
