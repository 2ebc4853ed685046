# Two commands on a fresh machine with only python3:
#   make demo   create .venv, install robkin, run the paper examples through every representation
#   make test   create .venv, install robkin with its test dependencies, run the test suite
#   make docs   build the documentation site into site/ (strict)
PYTHON ?= python3
VENV   ?= .venv
PY     := $(VENV)/bin/python
PIP    := $(PY) -m pip --disable-pip-version-check -q

.PHONY: demo test bench ext docs clean

# The compiled core (src/robkin/compiled/*.pyx) is built by pip with the machine's C compiler.
CORE_SOURCES := pyproject.toml setup.py $(wildcard src/robkin/compiled/*.pyx src/robkin/compiled/*.pxd)

$(VENV)/.core: $(CORE_SOURCES)
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

# The documentation site (MkDocs Material + mkdocstrings) into site/; strict: a broken link or
# reference fails the build. The CLI reference is generated from the parsers (docs/hooks/).
docs: $(VENV)/.core
	$(PIP) install -e '.[docs]'
	NO_MKDOCS_2_WARNING=1 $(PY) -m mkdocs build --strict

# Rebuild the compiled core in place after editing a .pyx (pip install -e . does the same, slower).
ext: $(VENV)/.core
	$(PY) setup.py -q build_ext --inplace

clean:
	rm -rf $(VENV) build site src/*.egg-info .pytest_cache .hypothesis src/robkin/compiled/*.c src/robkin/compiled/*.so
