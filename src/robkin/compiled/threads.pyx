# cython: language_level=3
"""How many threads robkin's batch kernels use: one process-wide default, and the rule for a batch.

The batch kernels (FK, frames, Jacobians, dynamics, numeric IK) split their blocks of configurations, or
their targets, over OpenMP threads (``cython.parallel.prange``, dynamic schedule). Every configuration is
computed by the same code whatever the thread, so the results are the same bits with any number of
threads. The default is the ``ROBKIN_NUM_THREADS`` environment variable, else ``OMP_NUM_THREADS`` (what
process pools - joblib's loky, Dask's nanny, ``threadpoolctl`` users - set to share the cores out among
their workers), else the number of cores this process may run on; ``robkin.set_threads`` changes it. A batch too small for threads to pay uses one,
and so does a call made from a thread other than the main one (a Dask worker, a user's pool: they
already use the cores, and more threads would only contend) unless its ``threads=`` says otherwise.
"""

import _thread
import os
import sys

cdef extern from "Python.h":
    # the calling OS thread's identifier: safe without the GIL (pthread_self or its equivalent)
    unsigned long thread_ident "PyThread_get_thread_ident" () nogil

cdef extern from *:
    """
    #ifdef _OPENMP
    #define RK_OPENMP 1
    #else
    #define RK_OPENMP 0
    #endif
    """
    int RK_OPENMP

cdef int _default = 1
cdef unsigned long _main_thread = 0


def available_cores():
    """Cores this process may run on (its CPU affinity where the system has one)."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):
        return max(1, os.cpu_count() or 1)


def _from_environment():
    """ROBKIN_NUM_THREADS when it is a whole number >= 1 (robkin's command line checks the variable and
    says when it is not usable); else OMP_NUM_THREADS when it is one (or a list of them, OpenMP's
    nested form: its first); else the available cores. Capped at 1024."""
    for text in (os.environ.get("ROBKIN_NUM_THREADS", ""), os.environ.get("OMP_NUM_THREADS", "").split(",")[0]):
        text = text.strip()
        if text.isdigit() and int(text) >= 1:
            return min(int(text), 1024)
    return available_cores()


def set_default_threads(int n):
    """Set the process-wide default thread count (>= 1)."""
    global _default
    if n < 1:
        raise ValueError("threads must be >= 1")
    _default = n


def default_threads():
    """The process-wide default thread count."""
    return _default


def compiled_with_openmp():
    """True when this build runs batches on several threads (False: every batch runs on one)."""
    return bool(RK_OPENMP)


cdef int batch_threads(int requested, Py_ssize_t units, Py_ssize_t min_units) noexcept nogil:
    """Threads for a batch of ``units`` independent pieces of work (blocks of configurations, targets).

    requested >= 1: that many, but no more than there are units. requested <= 0 (automatic): the
    default, one in a thread other than the main one, and only as many as leave each thread at least
    ``min_units`` units (below that, starting threads costs more than it saves).
    """
    cdef Py_ssize_t cap
    cdef int t = requested
    if not RK_OPENMP:
        return 1
    if t <= 0:
        if thread_ident() != _main_thread:
            return 1
        t = _default
        cap = units // min_units
    else:
        cap = units
    if cap < t:
        t = <int>cap
    return t if t >= 1 else 1


_default = _from_environment()
# The main thread: threading's, if something imported threading already; else this thread, which is what
# threading itself would call main were it imported now (its main thread is the one that first imports it).
# Not importing threading saves ~0.8 ms of every command's start-up.
_main_thread = sys.modules["threading"].main_thread().ident if "threading" in sys.modules else _thread.get_ident()


def plan(int requested, Py_ssize_t units, Py_ssize_t min_units):
    """The thread count a batch kernel would use from this thread (``batch_threads``), for tests and
    for anyone tuning a pipeline."""
    return batch_threads(requested, units, min_units)
