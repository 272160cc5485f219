# Two commands do everything on a fresh machine: `make demo` and `make test`.
PY ?= python3
VENV := .venv
BIN := $(VENV)/bin
OUT ?= out

.PHONY: demo test test-slow verify bench setup clean

$(BIN)/bearingfem: pyproject.toml
	$(PY) -m venv $(VENV)
	$(BIN)/pip install --quiet --upgrade pip
	$(BIN)/pip install --quiet -e '.[test]'
	touch $@

setup: $(BIN)/bearingfem

demo: setup
	$(BIN)/bearingfem study seed000 --out $(OUT)/seed000
	@echo "report: $(OUT)/seed000/report.md"

verify: setup
	$(BIN)/bearingfem verify --out $(OUT)/verify

test: setup
	$(BIN)/python -m pytest -q

test-slow: setup
	$(BIN)/python -m pytest -q -m slow

bench: setup
	$(BIN)/bearingfem bench

clean:
	rm -rf $(OUT) .cache
