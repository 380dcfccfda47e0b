# geardyn: `make run` installs into .venv and runs the demo; `make test` runs the suite.
PY ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed-$(shell cat pyproject.toml | cksum | cut -d' ' -f1)

.PHONY: run test lint bench clean warmup

$(BIN)/python:
	$(PY) -m venv $(VENV)
	$(BIN)/python -m pip install -q --upgrade pip

# The warm-up compiles and caches every numba kernel (next to the sources), so that the first
# `geardyn simulate` loads machine code instead of compiling (docs/planetary.md, Speed).
$(STAMP): pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install -q -e ".[test]"
	$(BIN)/python -m geardyn.warmup
	rm -f $(VENV)/.installed-*
	touch $(STAMP)

warmup: $(STAMP)
	$(BIN)/python -m geardyn.warmup

run: $(STAMP)
	$(BIN)/geardyn demo

test: $(STAMP)
	$(BIN)/ruff check src tests benchmarks
	$(BIN)/python -m pytest -q

lint: $(STAMP)
	$(BIN)/ruff check src tests benchmarks

bench: $(STAMP)
	$(BIN)/python -m benchmarks

clean:
	rm -rf $(VENV) build src/*.egg-info .pytest_cache
