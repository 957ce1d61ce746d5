# Every target sets itself up: Debian packages (python3-venv, yade) and the
# virtual environment with the pinned packages (scripts/bootstrap.sh).
VENV ?= .venv
PY := $(VENV)/bin/python
JOBS ?=
export OPENBLAS_NUM_THREADS ?= 1
export OMP_NUM_THREADS ?= 1

.PHONY: setup test test-fast validate bench catalog clean

setup:
	@bash scripts/bootstrap.sh

# the whole suite, one pytest-xdist worker per core; each test file stays on one worker (--dist
# loadfile), so a module's fixtures are computed once and at most one DEM run goes per core
test: setup
	$(PY) -m pytest -q -n auto --dist loadfile tests

# the fast subset for every change: no DEM engine, no slow test (CONTRIBUTING.md), one pytest-xdist
# worker per core (-n auto; PYTEST_XDIST_AUTO_NUM_WORKERS=N sets another number)
test-fast: setup
	$(PY) -m pytest -q -n auto -m "not yade and not lmgc90 and not slow" tests

validate: setup
	$(PY) -m reports.validate $(if $(JOBS),--jobs $(JOBS))

bench: setup
	$(PY) -m bench.run

catalog: setup
	$(PY) -m scenes.catalog

clean:
	rm -rf reports/out bench/out results .cache
