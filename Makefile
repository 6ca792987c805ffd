# rv-bearing-sweep: `make sweep` and `make test` build .venv on first use.
# Bytecode: where PYTHONDONTWRITEBYTECODE is set (this machine, many containers) Python never
# caches what it compiles, and every process (each of a sweep's workers, each test process)
# compiled its 1,400 imported modules again, 3.4 s each. So make's commands write the caches
# (into .venv/ and the tree's git-ignored __pycache__/), and `make venv` writes those of what
# the commands import (tools/compile_bytecode.py: pip's own compile of every installed file
# took about 20 s more) for running rvsweep outside make.
unexport PYTHONDONTWRITEBYTECODE
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
TESTSTAMP := $(VENV)/.installed-test
SWEEP  ?= sweeps/study.toml
OUT    ?= results
TESTARGS ?=
# make test spreads the tests over this many processes (pytest-xdist); 1 runs them in one.
TESTWORKERS ?= 2
REPORTARGS ?=  # options of rvsweep report, e.g. REPORTARGS='--target-s0 2 --target-life 50'

.DEFAULT_GOAL := help
.PHONY: help venv sweep smoke report test test-all bench clean

help:  ## list the targets
	@grep -E '^[a-z-]+:.*## ' $(MAKEFILE_LIST) | awk -F':.*## ' '{printf "  make %-10s %s\n", $$1, $$2}'

# The package alone for the sweeps and reports; with its test extras (pytest, hypothesis,
# compliance-checker and what they need) for the tests, in one install where the tests
# come first. tools/install_venv.sh makes the venv: uv installs, from a copy kept per user,
# against the index at most once a day (pip where uv cannot); then the bytecode of what
# the commands import (tools/compile_bytecode.py).
define install
	PYTHON=$(PYTHON) VENV=$(VENV) bash tools/install_venv.sh '$(1)'
	$(BIN)/python tools/compile_bytecode.py
endef

$(STAMP): pyproject.toml
	$(call install,.)
	touch $(STAMP)

$(TESTSTAMP): pyproject.toml
	$(call install,.[test])
	touch $(STAMP) $(TESTSTAMP)

venv: $(TESTSTAMP)  ## create .venv and install the package with its test extras

# The report in the sweep's own process (--report): its imports are the sweep's, 1.2-1.6 s
# less than a second command.
sweep: $(STAMP)  ## run SWEEP (default sweeps/study.toml) into OUT/<name>, then its report
	$(BIN)/rvsweep sweep $(SWEEP) --out $(OUT) --report $(REPORTARGS)

smoke:  ## the 3x3 smoke sweep (9 cases, 8-16 s; a first run compiles numba first)
	$(MAKE) sweep SWEEP=sweeps/smoke.toml

report: $(STAMP)  ## the report for the last sweep of SWEEP (REPORTARGS: e.g. '--target-s0 2')
	$(BIN)/rvsweep report $(OUT)/$$($(BIN)/python -c "import sys,tomllib;print(tomllib.load(open(sys.argv[1],'rb')).get('name'))" $(SWEEP)) $(REPORTARGS)

test: $(TESTSTAMP)  ## the default test run (slow tests excluded), on TESTWORKERS processes
	$(BIN)/python -m pytest -q -n $(TESTWORKERS) --dist loadgroup $(TESTARGS)

test-all: $(TESTSTAMP)  ## every test, the slow physics checks included
	$(BIN)/python -m pytest -q -n $(TESTWORKERS) --dist loadgroup -m "" $(TESTARGS)

bench: $(STAMP)  ## performance figures of the core and the sweep
	$(BIN)/rvsweep bench

clean:  ## remove build and cache files (keeps .venv and results)
	rm -rf .pytest_cache .hypothesis build dist
	find . -name __pycache__ -prune -exec rm -rf {} +
