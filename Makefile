# Two commands do everything on a fresh machine: `make demo` and `make test`.
PY ?= python3
VENV := .venv
BIN := $(VENV)/bin
OUT ?= out

.PHONY: demo test test-slow verify bench setup clean

# the extras: test (pytest, xdist, pypdf) and ross (the ROSS round trip of `stiffness --ross`,
# tests/test_stiffness_ross.py, which `make test` then requires: BEARINGFEM_REQUIRE_ROSS)
$(BIN)/bearingfem: pyproject.toml Makefile
	$(PY) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -e '.[test,ross]'
	touch $@

setup: $(BIN)/bearingfem

demo: setup
	$(BIN)/bearingfem study seed000 --out $(OUT)/seed000
	@echo "report: $(OUT)/seed000/report.md"

verify: setup
	$(BIN)/bearingfem verify --out $(OUT)/verify

# the suite on every core up to 4, one test module per worker (module fixtures built once; on 2
# workers the modules' CPU split 109 / 107 s with a cold FE cache, 82 / 85 s warm, 2026-12-02,
# docs/benchmarks.md: loadscope balances, worksteal would only build the modules' pipelines twice)
PYTEST_PAR := -n auto --maxprocesses 4 --dist loadscope

# bytecode caches on even where the environment turns them off (PYTHONDONTWRITEBYTECODE): the
# assertion rewriting and compiling of the project's modules is then done once, not on every run
# by every worker (collection 17 -> 9 s on this machine, 2026-11-29)
PYTEST_ENV := PYTHONDONTWRITEBYTECODE=

test: setup
	$(PYTEST_ENV) BEARINGFEM_REQUIRE_ROSS=1 $(BIN)/python -m pytest -q $(PYTEST_PAR)

test-slow: setup
	$(PYTEST_ENV) $(BIN)/python -m pytest -q -m slow $(PYTEST_PAR)

bench: setup
	$(BIN)/bearingfem bench

clean:
	rm -rf $(OUT) .cache
