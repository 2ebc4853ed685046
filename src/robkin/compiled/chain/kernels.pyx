# cython: language_level=3
"""Which build of the batch block kernels runs: portable or AVX2, chosen once at import from the CPU.

The batch kernels (FK, frames, Jacobians, inverse dynamics, mass matrices) spend their time in loops
over a block of up to 32 configurations that the compiler turns into SIMD code. The portable build
(``-O3``, no ``-march``: x86-64's baseline, SSE2) runs 2 doubles per instruction; the same source
compiled with ``-mavx2`` runs 4. ``kernel_bodies.pxi`` is therefore compiled twice, here (portable)
and in ``kernels_avx2`` (only that module gets ``-mavx2``: the wheel still runs on any x86-64), and
the other modules ask ``active_kernels()`` for the table of function pointers to call.

Why two builds of one source, not GCC's ``target_clones`` (which ``sincos.h`` uses): the kernels are
Cython functions, which cannot carry a C attribute, and a ``#pragma GCC target`` would also compile the
module's initialisation for AVX2; clones also need GCC with glibc's ifuncs, two builds need only a
compiler that takes ``-mavx2`` (GCC, Clang). The choice costs one indirect call per block of 32
configurations. Single-configuration calls keep their inlined portable path (one configuration fills
no SIMD lanes), and the results are the same bits whichever build runs: both do the same IEEE
operations in the same order (``-ffp-contract=off``, no FMA, no ``-ffast-math``).

The choice: ``ROBKIN_KERNELS`` = ``auto`` (default: AVX2 when the CPU has it and it was built),
``portable`` or ``avx2`` (falls back to portable, with a warning, when the CPU or the build lacks it).
``use(name)`` switches later (tests, benchmarks; not while a batch runs in another thread).
"""

import importlib
import os
import warnings

from cpython.pycapsule cimport PyCapsule_GetPointer

include "kernel_bodies.pxi"

cdef extern from *:
    """
    /* The CPU runs AVX2 and the OS saves its registers (libgcc's check reads both). */
    static int rk_cpu_has_avx2(void)
    {
    #if (defined(__GNUC__) || defined(__clang__)) && (defined(__x86_64__) || defined(__i386__))
        __builtin_cpu_init();
        return __builtin_cpu_supports("avx2") ? 1 : 0;
    #else
        return 0;
    #endif
    }
    """
    int rk_cpu_has_avx2() nogil

CHOICES = ("auto", "portable", "avx2")

cdef const BlockKernels* _active = &TABLE
cdef const BlockKernels* _avx2 = NULL
_active_name = "portable"


cdef const BlockKernels* active_kernels() noexcept nogil:
    """The table of batch block kernels chosen for this process (``kernel_table.pxd``)."""
    return _active


def cpu_has_avx2():
    """True when this CPU (and its OS) runs AVX2 instructions."""
    return bool(rk_cpu_has_avx2())


def avx2_built():
    """True when this installation has the AVX2 build of the kernels (x86-64 with a compiler that
    takes -mavx2); says nothing about whether this CPU can run it."""
    if _avx2 != NULL:
        return True
    import importlib.util
    return importlib.util.find_spec("robkin.compiled.chain.kernels_avx2") is not None


def choose(requested, cpu_avx2, built):
    """The build to run and a warning (or None) for a request, a CPU and an installation.

    Parameters
    ----------
    requested : str
        ``ROBKIN_KERNELS``'s value: 'auto' (or ''), 'portable' or 'avx2' (case and spaces ignored).
    cpu_avx2 : bool
        The CPU runs AVX2 (``cpu_has_avx2()``).
    built : bool
        The AVX2 build is installed (``avx2_built()``).

    Returns
    -------
    (str, str or None)
        'portable' or 'avx2', and why a request could not be followed.
    """
    text = (requested or "auto").strip().lower() or "auto"
    if text not in CHOICES:
        return ("avx2" if cpu_avx2 and built else "portable",
                f"ROBKIN_KERNELS={requested!r} is not one of auto, portable, avx2: using auto")
    if text == "portable":
        return "portable", None
    if cpu_avx2 and built:
        return "avx2", None
    if text == "avx2":
        why = "this CPU has no AVX2" if not cpu_avx2 else "robkin was built without the AVX2 kernels"
        return "portable", f"ROBKIN_KERNELS=avx2 but {why}: using the portable kernels"
    return "portable", None


cdef const BlockKernels* _load_avx2() except? NULL:
    """The AVX2 table, importing its module on first use (callers have checked the CPU)."""
    global _avx2
    if _avx2 == NULL:
        module = importlib.import_module("robkin.compiled.chain.kernels_avx2")
        _avx2 = <const BlockKernels*>PyCapsule_GetPointer(module.TABLE_CAPSULE,
                                                          b"robkin.compiled.chain.kernels_avx2.TABLE")
    return _avx2


def use(name):
    """Run the batch kernels of one build from now on: 'auto', 'portable' or 'avx2'.

    Returns the build now running. Raises ValueError for another name and RuntimeError when 'avx2' is
    asked on a CPU without AVX2 or an installation without that build. For tests and benchmarks: do
    not switch while a batch runs in another thread.
    """
    global _active, _active_name
    if name not in CHOICES:
        raise ValueError(f"kernels: expected one of {', '.join(CHOICES)}, got {name!r}")
    chosen, why = choose(name, cpu_has_avx2(), avx2_built())
    if why is not None:
        raise RuntimeError(why)
    _active = _load_avx2() if chosen == "avx2" else &TABLE
    _active_name = chosen
    return chosen


def active():
    """The build of the batch kernels running now: 'portable' or 'avx2'."""
    return _active_name


def _from_environment():
    """Follow ROBKIN_KERNELS at import (a request that cannot be followed warns and runs portable)."""
    global _active, _active_name
    requested = os.environ.get("ROBKIN_KERNELS", "auto")
    cpu = cpu_has_avx2()
    built = False
    if cpu and requested.strip().lower() != "portable":
        try:                    # the import is the test of the build (cheaper than a search for it)
            _load_avx2()
            built = True
        except ImportError:     # not built here: the portable kernels give the same results
            pass
    chosen, why = choose(requested, cpu, built)
    if why is not None:
        warnings.warn(why, RuntimeWarning, stacklevel=2)
    _active = _avx2 if chosen == "avx2" else &TABLE
    _active_name = chosen
    return chosen


_from_environment()
