# Two commands on a fresh machine with only python3:
#   make demo   create .venv, install robkin, run the paper examples through every representation
#   make test   create .venv, install robkin with its test dependencies, run the test suite
PYTHON ?= python3
VENV   ?= .venv
PY     := $(VENV)/bin/python
PIP    := $(PY) -m pip --disable-pip-version-check -q

.PHONY: demo test bench clean

$(VENV)/.core: pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PIP) install -e .
	touch $@

$(VENV)/.test: $(VENV)/.core
	$(PIP) install -e '.[test]'
	touch $@

demo: $(VENV)/.core
	$(VENV)/bin/robkin demo

test: $(VENV)/.test
	$(PY) -m pytest -q

# Benchmarks compare against peers in the same run (pinocchio; the Robotics Toolbox where it installs).
bench: $(VENV)/.test
	$(PIP) install -e '.[test,bench]'
	for b in benchmarks/bench_*.py; do echo "== $$b"; $(PY) $$b || exit 1; done

clean:
	rm -rf $(VENV) build src/*.egg-info .pytest_cache .hypothesis
