"""Build the compiled kinematics core (``robkin.compiled``) from its Cython sources.

Everything else about the package lives in ``pyproject.toml``. Each ``.pyx`` under ``src/robkin/compiled/``
(in its topic's sub-package: ``chain/``, ``ik/``, ``conversions/``, ``scanners/``, ``runtime/``) becomes
one extension module named by its path (``chain/fk.pyx``: ``robkin.compiled.chain.fk``); ``pip install
-e .`` (``make demo`` / ``make test``) builds them with the machine's C compiler, and ``make ext``
rebuilds them in place after editing a ``.pyx``.

C headers are named by their path under ``src/robkin/compiled/`` (``cdef extern from
"runtime/sincos.h"``), which every extension has on its include path: ``sincos.h`` is included by
modules of several sub-packages (through ``runtime/sincos.pxd``).
"""

import os
import sys
import tempfile
from pathlib import Path

import numpy
from Cython.Build import cythonize
from setuptools import Extension, setup

HERE = Path(__file__).parent
COMPILED = HERE / "src" / "robkin" / "compiled"
SOURCES = sorted(COMPILED.rglob("*.pyx"))


def module_name(path: Path) -> str:
    """The dotted name of the extension built from one .pyx: ``robkin.compiled.chain.fk``."""
    return ".".join(("robkin", "compiled", *path.relative_to(COMPILED).with_suffix("").parts))



def openmp_flags() -> list[str]:
    """``-fopenmp`` when the C compiler takes it (GCC, Clang with libomp): the batch kernels then split
    large batches over threads (``robkin.compiled.runtime.threads``). Without it they run on one thread,
    with the same results. ROBKIN_NO_OPENMP=1 builds without."""
    if os.environ.get("ROBKIN_NO_OPENMP") == "1" or sys.platform == "win32":
        return []
    from setuptools._distutils.ccompiler import new_compiler
    from setuptools._distutils.sysconfig import customize_compiler

    compiler = new_compiler()
    customize_compiler(compiler)
    with tempfile.TemporaryDirectory() as tmp:
        src = Path(tmp) / "probe.c"
        src.write_text("#include <omp.h>\nint main(void) { return omp_get_max_threads() > 0 ? 0 : 1; }\n")
        try:
            objects = compiler.compile([str(src)], output_dir=tmp, extra_postargs=["-fopenmp"])
            compiler.link_executable(objects, str(Path(tmp) / "probe"), extra_postargs=["-fopenmp"])
        except Exception:  # any compiler or linker failure: build without threads
            return []
    return ["-fopenmp"]


OPENMP = openmp_flags()


def avx2_flags() -> list[str] | None:
    """``-mavx2`` for the one module built for AVX2 (``robkin.compiled.chain.kernels_avx2``, chosen at
    import by the CPU, see ``chain/kernels.pyx``) when the target is x86-64 and the C compiler takes the
    flag; else None and that module is not built (the portable kernels run, with the same results). Only
    -mavx2: no -mfma (with -ffp-contract=off there would be no fused multiply-add anyway) and no -march, so
    the module's code is the portable one's at twice the vector width. ROBKIN_NO_AVX2=1 builds without."""
    import platform

    if os.environ.get("ROBKIN_NO_AVX2") == "1" or platform.machine().lower() not in ("x86_64", "amd64"):
        return None
    from setuptools._distutils.ccompiler import new_compiler
    from setuptools._distutils.sysconfig import customize_compiler

    compiler = new_compiler()
    customize_compiler(compiler)
    with tempfile.TemporaryDirectory() as tmp:
        src = Path(tmp) / "probe.c"
        src.write_text("#include <immintrin.h>\nint probe(void) { __m256i a = _mm256_set1_epi64x(1); "
                       "return _mm256_extract_epi32(_mm256_add_epi64(a, a), 0); }\n")
        try:
            compiler.compile([str(src)], output_dir=tmp, extra_postargs=["-mavx2"])
        except Exception:  # a compiler without the flag (or not for x86): the portable kernels only
            return None
    return ["-mavx2"]


AVX2 = avx2_flags()


def instruction_flags(path: Path) -> list[str] | None:
    """Extra flags for one module: ``-mavx2`` for the ``*_avx2.pyx`` builds (None: skip it)."""
    if path.stem.endswith("_avx2"):
        return AVX2
    return []


extensions = [
    Extension(
        module_name(path),
        [str(path.relative_to(HERE))],
        # compiled/ itself: the headers, named by their path under it ("chain/crba_walk.h")
        include_dirs=[numpy.get_include(), str(COMPILED.relative_to(HERE))],
        define_macros=[("NPY_NO_DEPRECATED_API", "NPY_1_7_API_VERSION")],
        # -O3 for the small fixed-size loops and the block loops over configurations (auto-vectorised);
        # no -ffast-math: results must stay IEEE-exact so the compiled core agrees with the independent
        # oracles to rounding. -ffp-contract=off: no fused multiply-adds, which a compiler may use in a
        # vectorised loop and not in its scalar remainder; single and batch results stay bit-for-bit equal.
        extra_compile_args=["-O3", "-ffp-contract=off", "-fno-tree-loop-distribute-patterns", *OPENMP,
                            *instruction_flags(path)],
        extra_link_args=OPENMP,
    )
    for path in SOURCES
    if instruction_flags(path) is not None
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
