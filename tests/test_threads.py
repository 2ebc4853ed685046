"""Batch kernels on several threads (robkin.threads): the same bits as one thread and as single calls."""

from __future__ import annotations

import os
import subprocess
import sys
import threading
import warnings
from pathlib import Path

import numpy as np
import pytest

import robkin
from robkin import InputError
from robkin.compiled.runtime import threads as compiled
from test_urdf import robot_file

ROOT = Path(__file__).resolve().parent.parent
needs_openmp = pytest.mark.skipif(not compiled.compiled_with_openmp(), reason="built without OpenMP")


@pytest.fixture(scope="module")
def panda() -> robkin.Robot:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return robkin.load(robot_file("panda_description/urdf/panda.urdf"), base_link="panda_link0",
                           tip_link="panda_leftfinger")      # 7R + a prismatic finger


@pytest.mark.parametrize("N", [33, 257, 1000, 4099])
def test_every_batch_kernel_gives_the_same_bits_on_any_number_of_threads(panda, N):
    rng = np.random.default_rng(N)
    Q, QD, QDD = (panda.random_q(N, rng) for _ in range(3))
    calls = [lambda t: panda.fk(Q, threads=t), lambda t: panda.frames_at(Q, threads=t),
             lambda t: panda.jacobian(Q, threads=t), lambda t: panda.jacobian(Q, "body", threads=t),
             lambda t: panda.manipulability(Q, "full", threads=t),
             lambda t: panda.inverse_dynamics(Q, QD, QDD, threads=t), lambda t: panda.gravity(Q, threads=t),
             lambda t: panda.mass_matrix(Q, threads=t)]
    for call in calls:
        one = call(1)
        for t in (2, 3, 8, None):
            assert np.array_equal(call(t), one)
    # and a batch equals its single calls (the last of each block edge)
    for k in (0, 31, 32, N - 1):
        assert np.array_equal(panda.fk(Q, threads=4)[k], panda.fk(Q[k]))
        assert np.array_equal(panda.jacobian(Q, threads=4)[k], panda.jacobian(Q[k]))


def test_numeric_ik_answers_do_not_depend_on_threads(panda):
    T = panda.fk(panda.random_q(24, rng=7))
    one = panda.ik(T, method="numeric", threads=1)
    for t in (2, 5, None):
        other = panda.ik(T, method="numeric", threads=t)
        assert np.array_equal(other.q, one.q) and np.array_equal(other.success, one.success)
        assert np.array_equal(other.iterations, one.iterations)


@needs_openmp
def test_automatic_thread_count_rules():
    default = compiled.default_threads()
    assert compiled.plan(0, 1, 8) == 1                    # too small to split
    assert compiled.plan(0, 10_000, 8) == default          # large: the default
    assert compiled.plan(3, 2, 8) == 2                     # asked: at most one thread per unit
    assert compiled.plan(3, 10_000, 8) == 3
    seen = []
    worker = threading.Thread(target=lambda: seen.extend([compiled.plan(0, 10_000, 8), compiled.plan(2, 10_000, 8)]))
    worker.start()
    worker.join()
    assert seen == [1, 2]   # another thread (a Dask worker, a pool) gets one unless it asks


def test_set_threads_and_bad_values(panda):
    before = robkin.get_threads()
    try:
        robkin.set_threads(3)
        assert robkin.get_threads() == 3
        robkin.set_threads(None)
        assert robkin.get_threads() == compiled._from_environment()
    finally:
        robkin.set_threads(before)
    for bad in (0, -1, 1.5, "2", True):
        with pytest.raises(InputError, match="threads: expected a whole number >= 1"):
            panda.fk(np.zeros(panda.n), threads=bad)
    with pytest.raises(InputError, match="threads"):
        robkin.set_threads(0)


def test_environment_variable(monkeypatch):
    monkeypatch.delenv("OMP_NUM_THREADS", raising=False)
    monkeypatch.setenv("ROBKIN_NUM_THREADS", "3")
    assert compiled._from_environment() == 3
    for unusable in ("0", "abc", "", "-2"):
        monkeypatch.setenv("ROBKIN_NUM_THREADS", unusable)
        assert compiled._from_environment() == compiled.available_cores()


def test_omp_num_threads_is_the_fallback(monkeypatch):
    """Process pools (joblib's loky, Dask's nanny) share the cores out through OMP_NUM_THREADS: robkin
    follows it unless ROBKIN_NUM_THREADS says otherwise."""
    monkeypatch.delenv("ROBKIN_NUM_THREADS", raising=False)
    monkeypatch.setenv("OMP_NUM_THREADS", "1")
    assert compiled._from_environment() == 1
    monkeypatch.setenv("OMP_NUM_THREADS", "5,2")              # OpenMP's nested form: the outer level
    assert compiled._from_environment() == 5
    monkeypatch.setenv("ROBKIN_NUM_THREADS", "2")
    assert compiled._from_environment() == 2
    monkeypatch.delenv("ROBKIN_NUM_THREADS")
    for unusable in ("0", "many", "", " ,3"):
        monkeypatch.setenv("OMP_NUM_THREADS", unusable)
        assert compiled._from_environment() == compiled.available_cores()


@needs_openmp
@pytest.mark.skipif(not hasattr(os, "sched_getaffinity") or len(os.sched_getaffinity(0)) < 2,
                    reason="needs Linux and two CPUs to run on")
def test_workers_are_kept_off_the_main_threads_cpu(panda):
    """After a batch on two threads from the main thread, its OpenMP worker may run on every CPU of the
    main thread but the one the main thread was on (``thread_placement.h``: a woken worker queued
    behind the main thread made two threads 3-20x slower than one on a busy machine); the same bits."""
    Q = panda.random_q(20_000, np.random.default_rng(3))
    assert np.array_equal(panda.fk(Q, threads=2), panda.fk(Q, threads=1))
    tids, off, placing = compiled.placement()
    if not placing:
        pytest.skip("placement is off here (OMP_PROC_BIND, OMP_PLACES, GOMP_CPU_AFFINITY or ROBKIN_PLACE_THREADS=0)")
    mine = os.sched_getaffinity(0)
    assert len(tids) >= 1 and off in mine
    for tid in tids:
        assert os.sched_getaffinity(tid) == mine - {off}


@pytest.mark.parametrize("env", [{"ROBKIN_PLACE_THREADS": "0"}, {"OMP_PROC_BIND": "close"}])
def test_workers_are_left_alone_when_asked_or_bound_by_openmp(env):
    """ROBKIN_PLACE_THREADS=0, or OpenMP's own binding asked for, leaves the workers' CPUs as they are."""
    code = ("import numpy as np, robkin\n"
            "from robkin.compiled.runtime import threads\n"
            "r = robkin.load('src/robkin/examples/iiwa14.yaml')\n"
            "r.fk(r.random_q(20000), threads=2)\n"
            "print(threads.placement())\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT,
                          env={**os.environ, **env}, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.strip() == "([], -1, False)"


@needs_openmp
@pytest.mark.skipif(not hasattr(os, "fork"), reason="needs os.fork")
def test_a_forked_child_runs_on_one_thread_and_does_not_hang():
    """A child forked after the parent ran threads (a multiprocessing pool with the fork start method)
    gets one thread: GNU OpenMP's pool does not survive a fork, and a parallel region there used to wait
    forever for the parent's threads. The same bits; the parent keeps its threads."""
    code = ("import os, numpy as np, robkin\n"
            "from robkin.compiled.runtime import threads\n"
            "r = robkin.load('src/robkin/examples/iiwa14.yaml')\n"
            "Q = r.random_q(20000, np.random.default_rng(0))\n"
            "a = r.fk(Q, threads=2)\n"
            "pid = os.fork()\n"
            "if pid == 0:\n"
            "    ok = threads.plan(2, 1000, 1) == 1 and np.array_equal(r.fk(Q, threads=2), a)\n"
            "    os._exit(0 if ok else 3)\n"
            "_, status = os.waitpid(pid, 0)\n"
            "print(os.waitstatus_to_exitcode(status), threads.plan(2, 1000, 1))\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, cwd=ROOT, timeout=120)
    assert done.returncode == 0, done.stderr
    assert done.stdout.split() == ["0", "2"]


def test_out_arrays_are_written_and_checked(panda):
    """``out=`` writes a batch into memory the caller owns: the same bits, the same array back, and a
    large batch walked in chunks through one buffer equals the whole batch at once."""
    Q = panda.random_q(300, rng=3)
    T = np.empty((300, 4, 4))
    assert panda.fk(Q, out=T) is T and np.array_equal(T, panda.fk(Q))
    F = np.empty((300, panda.n + 1, 4, 4))
    assert panda.frames_at(Q, out=F) is F and np.array_equal(F, panda.frames_at(Q))
    J = np.empty((300, 6, panda.n))
    for frame in ("base", "space", "body"):
        assert panda.jacobian(Q, frame, out=J) is J and np.array_equal(J, panda.jacobian(Q, frame))
    whole, buf, chunks = panda.fk(Q), np.empty((100, 4, 4)), []
    for k in range(0, 300, 100):
        chunks.append(panda.fk(Q[k:k + 100], out=buf).copy())
    assert np.array_equal(np.concatenate(chunks), whole)
    # lists are validated first, then written into out
    assert np.array_equal(panda.fk(Q[:2].tolist(), out=T[:2]), whole[:2])
    for bad in (np.empty((300, 4, 4), dtype=np.float32), np.empty((299, 4, 4)), np.empty((300, 4, 4))[:, :, ::-1],
                [[0.0] * 4] * 4):
        with pytest.raises(InputError, match="out: expected a writeable C-contiguous float64 array of shape"):
            panda.fk(Q.tolist(), out=bad)
    with pytest.raises(InputError, match="out: not available for frame='tool'"):
        panda.jacobian(Q, "tool", out=J)


@pytest.mark.parametrize("N", [63, 64, 65, 32 * 24 * 2 + 1])
def test_block_edges_and_manipulability_batches_give_the_same_bits(panda, N):
    """Batches a block (32) either side of an edge, split over two threads (the guided schedule hands out
    uneven stretches of blocks): the same bits as one thread and as the single calls, and a batch's
    manipulability (measured block by block in per-thread scratch) the same bits as the measure taken
    on the whole batch's Jacobians."""
    from robkin.compiled.chain.jacobian import volumes

    Q = panda.random_q(N, rng=N)
    J = panda.jacobian(Q, threads=1)
    for t in (1, 2):
        assert np.array_equal(panda.fk(Q, threads=t), panda.fk(Q, threads=1))
        assert np.array_equal(panda.frames_at(Q, threads=t), panda.frames_at(Q, threads=1))
        assert np.array_equal(panda.jacobian(Q, "space", threads=t), panda.jacobian(Q, "space", threads=1))
        for kind, rows in (("translational", slice(0, 3)), ("rotational", slice(3, 6)), ("full", slice(0, 6))):
            w = panda.manipulability(Q, kind, threads=t)
            assert w.shape == (N,) and np.array_equal(w, volumes(J[:, rows, :]))
    for k in (0, 31, 32, 33, N - 1):
        assert np.array_equal(panda.frames_at(Q, threads=2)[k], panda.frames_at(Q[k]))
        assert panda.manipulability(Q, "full", threads=2)[k] == panda.manipulability(Q[k], "full")
    # Yoshikawa's measure is the product of the singular values (numpy's LAPACK SVD, an independent
    # computation: 1e-12 relative is ~1e4 ulp, far above the two factorisations' rounding on 6 x 8)
    assert np.allclose(panda.manipulability(Q, "full", threads=2),
                       np.prod(np.linalg.svd(J, compute_uv=False), axis=-1), rtol=1e-12, atol=0)


@pytest.mark.parametrize("where", [0, 700, 1599])
def test_a_value_that_is_not_finite_is_found_in_any_block_on_any_thread(panda, where):
    """The batch kernels check each block's values on the thread that walks it: a NaN or an infinity in
    any block, on one thread or two, is still the one clear error (naming q), never a result."""
    Q = panda.random_q(1600, rng=1)
    for bad in (np.nan, np.inf):
        Qb = Q.copy()
        Qb[where, 3] = bad
        for t in (1, 2):
            for call in (lambda: panda.fk(Qb, threads=t), lambda: panda.frames_at(Qb, threads=t),
                         lambda: panda.jacobian(Qb, threads=t), lambda: panda.jacobian(Qb, "body", threads=t),
                         lambda: panda.manipulability(Qb, threads=t),
                         lambda: panda.fk(Qb, threads=t, out=np.empty((1600, 4, 4))),
                         lambda: panda.jacobian(Qb, threads=t, out=np.empty((1600, 6, panda.n)))):
                with pytest.raises(InputError, match="q"):
                    call()
    with pytest.raises(InputError, match="q"):
        panda.manipulability(np.full(panda.n, np.nan))


def test_batches_allocate_their_result_and_nothing_of_the_batch_size_more(panda):
    """Memory stays bounded however large the batch: FK and Jacobians written into ``out=`` allocate no
    array at all, a fresh result is the only array of the batch's size, and manipulability needs no
    N x 6 x n Jacobians (numpy reports every array it allocates to tracemalloc; the kernels' per-thread
    scratch, a few kB from C's malloc, is not traced and does not grow with N)."""
    import tracemalloc

    N = 20_000
    Q = panda.random_q(N, rng=2)
    T, J = np.empty((N, 4, 4)), np.empty((N, 6, panda.n))
    small = 64 * 1024   # Python objects of a call (a few kB); any array of N rows is >= 160 kB

    def peak(call):
        tracemalloc.start()
        try:
            call()
            return tracemalloc.get_traced_memory()[1]
        finally:
            tracemalloc.stop()

    for t in (1, 2):
        assert peak(lambda: panda.fk(Q, threads=t, out=T)) < small
        assert peak(lambda: panda.frames_at(Q[:1000], threads=t, out=np.empty((1000, panda.n + 1, 4, 4)))) \
            < 1000 * (panda.n + 1) * 128 + small
        assert peak(lambda: panda.jacobian(Q, "body", threads=t, out=J)) < small
        assert peak(lambda: panda.jacobian(Q, threads=t)) < J.nbytes + small
        assert peak(lambda: panda.manipulability(Q, "full", threads=t)) < N * 8 + small
