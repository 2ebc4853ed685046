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
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy
from Cython.Build import cythonize
from Cython.Compiler import Options as CythonOptions
from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext

HERE = Path(__file__).parent
COMPILED = HERE / "src" / "robkin" / "compiled"
SOURCES = sorted(COMPILED.rglob("*.pyx"))


def module_name(path: Path) -> str:
    """The dotted name of the extension built from one .pyx: ``robkin.compiled.chain.fk``."""
    return ".".join(("robkin", "compiled", *path.relative_to(COMPILED).with_suffix("").parts))



def new_c_compiler():
    """The C compiler setuptools will build with (CC, CFLAGS, ... of the environment applied)."""
    from setuptools._distutils.ccompiler import new_compiler
    from setuptools._distutils.sysconfig import customize_compiler

    compiler = new_compiler()
    customize_compiler(compiler)
    return compiler


COMPILER_TYPE = new_c_compiler().compiler_type  # "unix" (GCC, Clang), "msvc", "mingw32", ...


def compiler_takes(flags: list[str], source: str = "int probe(void) { return 0; }\n", link: bool = False) -> bool:
    """Whether the C compiler compiles (and, with ``link``, links into an executable) a probe with ``flags``.
    Never for MSVC, which takes none of the GCC/Clang flags used here (it ignores an unknown option with a
    warning, so compiling would not tell). ``-Werror``: Clang accepts a GCC-only optimisation flag such as
    -fno-tree-loop-distribute-patterns with only a warning; the probe then refuses it."""
    if COMPILER_TYPE == "msvc":
        return False
    compiler = new_c_compiler()
    with tempfile.TemporaryDirectory() as tmp:
        src = Path(tmp) / "probe.c"
        src.write_text(source)
        try:
            objects = compiler.compile([str(src)], output_dir=tmp, extra_postargs=["-Werror", *flags])
            if link:
                compiler.link_executable(objects, str(Path(tmp) / "probe"), extra_postargs=flags)
        except Exception:  # any compiler or linker failure: the flag is not for this compiler
            return False
    return True


def openmp_flags() -> list[str]:
    """``-fopenmp`` when the C compiler takes it (GCC, Clang with libomp): the batch kernels then split
    large batches over threads (``robkin.compiled.runtime.threads``). Without it they run on one thread,
    with the same results. ROBKIN_NO_OPENMP=1 builds without."""
    if os.environ.get("ROBKIN_NO_OPENMP") == "1" or sys.platform == "win32":
        return []
    probe = "#include <omp.h>\nint main(void) { return omp_get_max_threads() > 0 ? 0 : 1; }\n"
    return ["-fopenmp"] if compiler_takes(["-fopenmp"], probe, link=True) else []


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
    probe = ("#include <immintrin.h>\nint probe(void) { __m256i a = _mm256_set1_epi64x(1); "
             "return _mm256_extract_epi32(_mm256_add_epi64(a, a), 0); }\n")
    return ["-mavx2"] if compiler_takes(["-mavx2"], probe) else None


AVX2 = avx2_flags()


def instruction_flags(path: Path) -> list[str] | None:
    """Extra flags for one module: ``-mavx2`` for the ``*_avx2.pyx`` builds (None: skip it)."""
    if path.stem.endswith("_avx2"):
        return AVX2
    return []


# The optimisation and floating-point flags of every module (GCC and Clang; MSVC takes none of them, and
# builds with its defaults). Each is probed on its own: a compiler without one still builds the others.
# ROBKIN_SANITIZE=1 (make sanitize) replaces -O3 by -O1 -g and adds AddressSanitizer and
# UndefinedBehaviorSanitizer, for a separate checking build (see sanitize_flags).
SANITIZE = os.environ.get("ROBKIN_SANITIZE") == "1"
SANITIZE_FLAGS = ["-fsanitize=address,undefined", "-fno-omit-frame-pointer", "-fno-sanitize-recover=undefined"]
OPTIMISE = ["-O1", "-g"] if SANITIZE else ["-O3"]
CORE_FLAGS = [flag for flag in (*OPTIMISE, "-ffp-contract=off", "-fno-tree-loop-distribute-patterns")
              if compiler_takes([flag])]
if SANITIZE:
    if not compiler_takes(SANITIZE_FLAGS, "int main(void) { return 0; }\n", link=True):
        sys.exit("setup.py: ROBKIN_SANITIZE=1 needs a C compiler with -fsanitize=address,undefined (GCC, Clang)")
    CORE_FLAGS += SANITIZE_FLAGS

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
        extra_compile_args=[*CORE_FLAGS, *OPENMP, *instruction_flags(path)],
        extra_link_args=[*OPENMP, *(SANITIZE_FLAGS if SANITIZE else [])],
    )
    for path in SOURCES
    if instruction_flags(path) is not None
]

class StrippedBuildExt(build_ext):
    """build_ext, then the debug symbols stripped from each extension module (``strip -S -x``, GNU and
    macOS binutils alike: about 19 MB of modules become about 4 MB; the exported PyInit_ symbols stay).
    A no-op on Windows (MSVC keeps debug information in separate .pdb files) and where there is no
    ``strip``; ROBKIN_KEEP_SYMBOLS=1 (and ROBKIN_SANITIZE=1) keep the symbols, for a debugger."""

    def build_extension(self, ext):
        super().build_extension(ext)
        strip = shutil.which("strip")
        if SANITIZE or os.environ.get("ROBKIN_KEEP_SYMBOLS") == "1" or sys.platform == "win32" or not strip:
            return
        try:
            subprocess.run([strip, "-S", "-x", self.get_ext_fullpath(ext.name)], check=True, capture_output=True)
        except (OSError, subprocess.CalledProcessError) as e:  # a strip for another format: keep the symbols
            print(f"setup.py: not stripped ({e})", file=sys.stderr)


# Cython's bounds checks: off in the release build; ROBKIN_SANITIZE=1 turns boundscheck on (an index outside a
# memoryview raises IndexError). wraparound stays off in both: with it on, a negative index would quietly
# read from the array's end where the release build reads before its start; off, the bounds check refuses
# it. (The sanitized build's "use boundscheck(False)" performance hints are silenced where Cython has them.)
DIRECTIVES = {"boundscheck": SANITIZE, "wraparound": False}
if SANITIZE and "show_performance_hints" in CythonOptions.get_directive_defaults():
    DIRECTIVES["show_performance_hints"] = False

# Every core of the machine compiles (cythonize translates, build_ext compiles the C in parallel).
JOBS = os.cpu_count() or 1

setup(
    cmdclass={"build_ext": StrippedBuildExt},
    options={"build_ext": {"parallel": JOBS}},
    ext_modules=cythonize(
        extensions,
        nthreads=JOBS,
        language_level=3,
        compiler_directives={**DIRECTIVES, "cdivision": True, "initializedcheck": False},
    )
)
