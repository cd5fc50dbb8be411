# Two commands do all set-up on a fresh machine:
#   make demo   generate the built-in data set and run the main job on it
#   make test   run the test suite (make test-parser: the parser's figures on takes of their own)
# Both create .venv and install tvmedit into it (editable) the first time, and are quick after.

PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed

.PHONY: demo test test-parser bench clean distclean

# A .venv that is missing, broken (no pip) or of a Python older than 3.11 is made anew.
$(STAMP): pyproject.toml
	@$(PYTHON) -c 'import sys; sys.exit(sys.version_info < (3, 11))' || \
	    { echo "tvmedit needs Python 3.11 or newer; $(PYTHON) is $$($(PYTHON) -V 2>&1). Run: make PYTHON=python3.11 ..."; exit 1; }
	@$(BIN)/python -c 'import sys, pip; sys.exit(sys.version_info < (3, 11))' 2>/dev/null || \
	    { rm -rf $(VENV) && $(PYTHON) -m venv $(VENV); }
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[test,report,dask]'
	@touch $(STAMP)

demo: $(STAMP)
	$(BIN)/python -m tvmedit.demo

# The tests run in one process a core (at most 8; pytest-xdist, an idle process taking
# tests from a busy one); the test data they share is made once (tests/conftest.py).
# The parser's cases on takes made for them alone (marked parser: the development suite's, a
# 20 fps and a slimmer-body capture) cost minutes to make: they are make test-parser, to run
# after a change to the parser, its features or the development suite.
# The suite starts hundreds of tvmedit processes. pip compiles the packages it installs, not
# an editable install's own sources, and where PYTHONDONTWRITEBYTECODE is set Python never
# writes what it compiles: each process compiled tvmedit anew (0.1-0.2 s). compileall does
# it once (and again only for a file that changed).
test: $(STAMP)
	@$(BIN)/python -m compileall -q engine player tvmedit
	$(BIN)/pytest -q -n auto --maxprocesses 8 --dist worksteal -m "not parser"

test-parser: $(STAMP)
	@$(BIN)/python -m compileall -q engine player tvmedit
	$(BIN)/pytest -q -n auto --maxprocesses 8 --dist worksteal -m parser

# Benchmarks also install the peers they measure against (pyrender).
bench: $(STAMP)
	$(BIN)/python -m pip install --quiet -e '.[test,report,dask,bench]'
	$(BIN)/python benchmarks/run_all.py

clean:
	rm -rf demo .cache .pytest_cache

distclean: clean
	rm -rf $(VENV) *.egg-info
