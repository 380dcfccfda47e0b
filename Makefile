# geardyn: `make run` installs into .venv and runs the demo; `make test` runs the suite.
PY ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed-$(shell cat pyproject.toml | cksum | cut -d' ' -f1)
# Written when the numba warm-up has compiled and cached every kernel (docs/planetary.md, Speed).
WARM := $(VENV)/.warm-$(shell cat pyproject.toml | cksum | cut -d' ' -f1)

.PHONY: run first-run test lint bench clean warmup

$(BIN)/python:
	$(PY) -m venv $(VENV)
	$(BIN)/python -m pip install -q --upgrade pip

$(STAMP): pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install -q -e ".[test]"
	rm -f $(VENV)/.installed-*
	touch $(STAMP)

# The warm-up compiles and caches every numba kernel (next to the sources), so that the first
# `geardyn simulate` loads machine code instead of compiling (docs/planetary.md, Speed).
$(WARM): $(STAMP)
	$(BIN)/python -m geardyn.warmup
	rm -f $(VENV)/.warm-*
	touch $(WARM)

warmup: $(STAMP)
	$(BIN)/python -m geardyn.warmup
	touch $(WARM)

run: $(STAMP)
	@$(MAKE) --no-print-directory first-run

# After the install: the demo compiles the few kernels it needs itself, while the full warm-up
# runs beside it at low priority on the other core (log: .venv/warmup.log), so the first run
# does not wait for kernels the demo never calls (benchmarks/bench_firstrun.py measures it).
first-run:
	@test -f $(WARM) || test -f $(VENV)/.warming || { (touch $(VENV)/.warming; \
		nice -n 10 $(BIN)/python -m geardyn.warmup > $(VENV)/warmup.log 2>&1 \
		&& rm -f $(VENV)/.warm-* && touch $(WARM); rm -f $(VENV)/.warming) & }
	$(BIN)/geardyn demo

# One pytest worker per core (pytest-xdist), a test file per worker at a time (module fixtures
# such as the simulated baselines are built once).
test: $(WARM)
	$(BIN)/ruff check src tests benchmarks
	$(BIN)/python -m pytest -q -n auto --dist loadfile

lint: $(STAMP)
	$(BIN)/ruff check src tests benchmarks

bench: $(WARM)
	$(BIN)/python -m benchmarks

clean:
	rm -rf $(VENV) build src/*.egg-info .pytest_cache
