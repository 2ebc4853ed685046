"""Build the compiled kinematics core (``robkin.compiled``) from its Cython sources.

Everything else about the package lives in ``pyproject.toml``. Each ``src/robkin/compiled/*.pyx``
becomes one extension module; ``pip install -e .`` (``make demo`` / ``make test``) builds them with the
machine's C compiler, and ``make ext`` rebuilds them in place after editing a ``.pyx``.
"""

import os
from pathlib import Path

import numpy
from Cython.Build import cythonize
from setuptools import Extension, setup

HERE = Path(__file__).parent
SOURCES = sorted((HERE / "src" / "robkin" / "compiled").glob("*.pyx"))

extensions = [
    Extension(
        f"robkin.compiled.{path.stem}",
        [str(path.relative_to(HERE))],
        include_dirs=[numpy.get_include()],
        define_macros=[("NPY_NO_DEPRECATED_API", "NPY_1_7_API_VERSION")],
        # -O3 for the small fixed-size loops and the block loops over configurations (auto-vectorised);
        # no -ffast-math: results must stay IEEE-exact so the compiled core agrees with the independent
        # oracles to rounding. -ffp-contract=off: no fused multiply-adds, which a compiler may use in a
        # vectorised loop and not in its scalar remainder; single and batch results stay bit-for-bit equal.
        extra_compile_args=["-O3", "-ffp-contract=off", "-fno-tree-loop-distribute-patterns"],
    )
    for path in SOURCES
]

# Every core of the machine compiles (cythonize translates, build_ext compiles the C in parallel).
JOBS = os.cpu_count() or 1

setup(
    options={"build_ext": {"parallel": JOBS}},
    ext_modules=cythonize(
        extensions,
        nthreads=JOBS,
        language_level=3,
        compiler_directives={"boundscheck": False, "wraparound": False, "cdivision": True,
                             "initializedcheck": False},
    )
)
