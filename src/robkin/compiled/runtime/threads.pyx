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
Before a parallel region started by the main thread, its workers are kept off the main thread's CPU
(``place_workers``, ``thread_placement.h``).
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

cdef extern from "runtime/thread_placement.h":
    int RK_PLACEMENT
    int rk_pid() noexcept nogil
    int rk_gettid() noexcept nogil
    int rk_current_cpu() noexcept nogil
    int rk_exclude_cpu(const int* tids, int count, int cpu) noexcept nogil

cdef extern from *:
    """
    #ifdef _OPENMP
    #include <omp.h>
    #define rk_omp_thread_num() omp_get_thread_num()
    #define rk_omp_num_threads() omp_get_num_threads()
    #else
    #define rk_omp_thread_num() 0
    #define rk_omp_num_threads() 1
    #endif
    """
    int rk_omp_thread_num() noexcept nogil
    int rk_omp_num_threads() noexcept nogil

from cython.parallel cimport parallel

cdef int _default = 1
cdef unsigned long _main_thread = 0

# The main thread's OpenMP workers (``thread_placement.h``): their kernel ids, how many are known, the
# CPU they were last kept off (-1: not yet), and whether to place them at all
cdef enum:
    MAX_WORKERS = 1023      # the workers placed at most (a larger team is left as OpenMP puts it)
cdef int _worker_tids[MAX_WORKERS]
cdef int _known_workers = 0
cdef int _learnt_for = 0             # the team size they were learnt for, and in which process
cdef int _learnt_in = 0
cdef int _team_size[1]
cdef int _placed_off = -1
# the process that started robkin's OpenMP threads (0: none yet); a forked child of it runs on one thread
cdef int _threads_used_in = 0
cdef bint _placing = False


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
    """Threads for a batch of ``units`` independent pieces of work (blocks of configurations, targets):
    ``thread_count``; called by a kernel right before its parallel region, it also keeps the main
    thread's workers off the CPU the main thread is on (``place_workers``)."""
    global _threads_used_in
    cdef int t = thread_count(requested, units, min_units)
    if t > 1:
        _threads_used_in = rk_pid()
        place_workers(t)
    return t


cdef void place_workers(int nt) noexcept nogil:
    """Before a parallel region of ``nt`` threads started by the main thread: its OpenMP workers may run
    on every CPU of the main thread's but the one the main thread is on (see ``thread_placement.h``
    for why). The workers' ids are learnt by a parallel region of their own whenever the team's size
    changes (OpenMP may start and end workers then); their CPUs are set again only when the main thread
    has moved (a system call per worker, ~1 us). Nothing is done off Linux, from another thread, where
    the user binds OpenMP's threads himself (OMP_PROC_BIND, OMP_PLACES, GOMP_CPU_AFFINITY) or sets
    ROBKIN_PLACE_THREADS=0, and nothing more once a placement has failed with freshly learnt ids."""
    global _placed_off, _placing
    cdef int cpu
    if not _placing or thread_ident() != _main_thread or nt - 1 > MAX_WORKERS:
        return
    if nt != _learnt_for or rk_pid() != _learnt_in:    # (a forked child: those ids are its parent's)
        learn_workers(nt)
    cpu = rk_current_cpu()
    if cpu == _placed_off or _known_workers == 0:
        return
    if rk_exclude_cpu(_worker_tids, _known_workers, cpu) != 0:
        learn_workers(nt)           # a worker may have ended since: learn them again, once
        if rk_exclude_cpu(_worker_tids, _known_workers, cpu) != 0:
            _placing = False
            return
    _placed_off = cpu


cdef void learn_workers(int nt) noexcept nogil:
    """The kernel ids of the workers of a team of ``nt`` threads started from this thread."""
    global _known_workers, _placed_off, _learnt_for, _learnt_in
    cdef int k = 0
    _team_size[0] = 0
    with parallel(num_threads=nt):
        k = rk_omp_thread_num()
        if k > 0:
            _worker_tids[k - 1] = rk_gettid()
        else:
            _team_size[0] = rk_omp_num_threads()   # (an element: shared, written by one thread)
    _known_workers = _team_size[0] - 1 if _team_size[0] > 1 else 0
    _placed_off = -1
    _learnt_for = nt
    _learnt_in = rk_pid()


cdef int thread_count(int requested, Py_ssize_t units, Py_ssize_t min_units) noexcept nogil:
    """Threads for a batch of ``units`` independent pieces of work (blocks of configurations, targets).

    One in a child forked from a process that had started robkin's threads (a ``multiprocessing`` pool
    with the fork start method): OpenMP's threads do not survive a fork. Otherwise:
    requested >= 1: that many, but no more than there are units. requested <= 0 (automatic): the
    default, one in a thread other than the main one, and only as many as leave each thread at least
    ``min_units`` units (below that, starting threads costs more than it saves).
    """
    cdef Py_ssize_t cap
    cdef int t = requested
    if not RK_OPENMP:
        return 1
    if _threads_used_in != 0 and _threads_used_in != rk_pid():
        # a child forked from a process whose OpenMP threads had started: GNU OpenMP's thread pool is
        # not carried over by fork, and a parallel region there waits forever for the parent's threads
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


_placing = bool(RK_PLACEMENT and RK_OPENMP) and os.environ.get("ROBKIN_PLACE_THREADS", "").strip() != "0" and not any(
    os.environ.get(name, "").strip() for name in ("OMP_PROC_BIND", "OMP_PLACES", "GOMP_CPU_AFFINITY"))


def plan(int requested, Py_ssize_t units, Py_ssize_t min_units):
    """The thread count a batch kernel would use from this thread (``batch_threads``), for tests and
    for anyone tuning a pipeline."""
    return thread_count(requested, units, min_units)


def placement():
    """The main thread's OpenMP workers as placed so far: (their kernel thread ids, the CPU they are
    kept off or -1, whether placing is on); for tests and diagnostics."""
    return [_worker_tids[k] for k in range(_known_workers)], _placed_off, bool(_placing)
