# swarmproof: `make verify` and `make test` each set up .venv when missing,
# install the project into it, then run. Only Python 3.11 (>= 3.10) and pip needed.
PYTHON ?= python3
VERIFY_ARGS ?=
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed-stamp

.PHONY: setup verify test test-slow test-all bench clean

## pip installs without compiling (one process); compileall then compiles the installed packages
## and swarmproof's own folders on every core (make setup 62 s -> 43 s here; docs/performance.md).
## The bytecode of swarmproof's folders serves every process of make verify, whose environment
## may forbid writing it (PYTHONDONTWRITEBYTECODE).
$(STAMP): pyproject.toml
	@test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --disable-pip-version-check --no-compile -e '.[dev]'
	@$(BIN)/python -m compileall -q -j 0 "$$($(BIN)/python -c 'import sysconfig; print(sysconfig.get_paths()["purelib"])')" \
	  swarmproof models invariants checkers reference_impl > /dev/null
	@touch $(STAMP)

setup: $(STAMP)

## The main job: every check over the bundled library, as one property matrix, compared with
## the shipped baseline of expected verdicts (verify-baseline.json; docs/ci.md): known findings
## (song2014's broken tree links, song2016's one-step lag, song2016-literal's deadlock, ...) are
## printed with their citations and keep the gate green; a regression fails it.  swarmproof's
## exit code (0 as the baseline says or better, 1 a regression, 3 inconclusive) is passed on
## (make itself then says "Error 1" and exits 2, as make does for any failed recipe).
BASELINE ?= verify-baseline.json
## the exploration rows on one local process per core (Dask; the same rows as one process: docs/ci.md)
VERIFY_WORKERS ?= auto
verify: setup
	@$(BIN)/swarmproof verify --baseline $(BASELINE) --workers $(VERIFY_WORKERS) $(VERIFY_ARGS); rc=$$?; \
	case $$rc in \
	  1) echo "make verify: swarmproof verify exited 1: a regression against $(BASELINE) (rows under REGRESSED, CHANGED, READING CHANGED or NEW): a finding about the algorithm, not the tool breaking";; \
	  2) echo "make verify: swarmproof verify exited 2: bad input (the line above says what and how to fix it)";; \
	  3) echo "make verify: swarmproof verify exited 3: a row is inconclusive (budget or timeout): not a pass";; \
	esac; exit $$rc

## The default suite (slow tests excluded; see tests/README.md), on every core (pytest-xdist;
## every test is independent of order and of the worker it runs on).  TEST_WORKERS=0 runs it in
## one process.  pytest's exit 5 (no test collected) is a failure, said as such.
## Bytecode is cached for the suite even where PYTHONDONTWRITEBYTECODE is set (it is on the
## project's machine): without the cache every xdist worker and every CLI subprocess a test starts
## compiles swarmproof again (collection 13.5 s a worker, 4 s cached; docs/performance.md).
TEST_WORKERS ?= auto
TEST_ARGS ?=
test: setup
	@PYTHONDONTWRITEBYTECODE= MPLBACKEND=Agg $(BIN)/python -m pytest -q -n $(TEST_WORKERS) --dist loadgroup $(TEST_ARGS); rc=$$?; \
	case $$rc in \
	  5) echo "make test: pytest collected no test (exit 5): the suite ran nothing, which is a failure (a broken collection or a -m/-k that deselects everything)";; \
	esac; exit $$rc

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
