# swarmproof: `make verify` and `make test` each set up .venv when missing,
# install the project into it, then run. Only Python 3.11 (>= 3.10) and pip needed.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed-stamp

.PHONY: setup verify test test-slow test-all bench clean

$(STAMP): pyproject.toml
	@test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --disable-pip-version-check -e '.[dev]'
	@touch $(STAMP)

setup: $(STAMP)

## The main job: every check over the bundled library, as one property matrix.
verify: setup
	$(BIN)/swarmproof verify

## The default suite (slow tests excluded; see tests/README.md).
test: setup
	MPLBACKEND=Agg $(BIN)/python -m pytest -q

## Long acceptance runs, on purpose.
test-slow: setup
	MPLBACKEND=Agg $(BIN)/python -m pytest -q -m slow

test-all: setup
	MPLBACKEND=Agg $(BIN)/python -m pytest -q -m 'slow or not slow'

## Performance figures recorded in docs/performance.md.
bench: setup
	MPLBACKEND=Agg $(BIN)/python benchmarks/run_all.py

clean:
	rm -rf $(VENV) build *.egg-info .hypothesis
