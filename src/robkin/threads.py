"""How many threads robkin's batch kernels use.

Batch FK, frames, Jacobians, dynamics and numeric IK split large batches over threads (OpenMP, in the
compiled core); every configuration is computed by the same code on any thread, so the results are the
same bits with one thread or many. The default thread count is, in order: ``set_threads(n)``, the
``ROBKIN_NUM_THREADS`` environment variable, ``OMP_NUM_THREADS`` (set by process pools such as joblib's
and Dask's to share the cores among their workers), the number of cores this process may run on. A batch too
small for threads to pay (a few hundred configurations, a couple of IK targets per thread) runs on one,
and so does a call from a thread other than the main one (a Dask worker, your own thread pool), unless
the call's ``threads=`` asks for more. Every batch method takes ``threads=`` to bound it per call; the
command line takes ``--threads N`` (``robkin fk``, ``robkin ik``).

On Linux the main thread's OpenMP workers are kept off the CPU the main thread is on (each may run on
every other CPU of the main thread's): woken for a batch on a machine whose other cores were busy, a
worker queued behind the main thread made two threads 3-20x slower than one. ``ROBKIN_PLACE_THREADS=0``
turns that off, and so does binding OpenMP's threads yourself (``OMP_PROC_BIND``, ``OMP_PLACES``,
``GOMP_CPU_AFFINITY``). A child forked from a process that had started robkin's threads (a
``multiprocessing`` pool with the fork start method) runs its batches on one thread: OpenMP's threads do
not survive a fork, and a parallel region there would wait for them forever.
"""

from __future__ import annotations

__all__ = ["set_threads", "get_threads", "available_cores", "parallel_build"]


def set_threads(threads: int | None) -> None:
    """Set the default number of threads of the batch kernels for this process.

    Parameters
    ----------
    threads : int >= 1, or None
        None goes back to the automatic default (ROBKIN_NUM_THREADS, else OMP_NUM_THREADS, else the
        cores available).
    """
    from .checks import check_threads
    from .compiled.runtime import threads as compiled

    compiled.set_default_threads(compiled._from_environment() if threads is None else check_threads(threads))


def get_threads() -> int:
    """The default number of threads of the batch kernels (see ``set_threads``)."""
    from .compiled.runtime import threads as compiled

    return int(compiled.default_threads())


def available_cores() -> int:
    """The number of cores this process may run on (its CPU affinity where the system has one)."""
    from .compiled.runtime import threads as compiled

    return int(compiled.available_cores())


def parallel_build() -> bool:
    """True when the compiled core was built with OpenMP (else every batch runs on one thread)."""
    from .compiled.runtime import threads as compiled

    return bool(compiled.compiled_with_openmp())
