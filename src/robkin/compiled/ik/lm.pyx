# cython: language_level=3
"""Levenberg-Marquardt inverse kinematics for one target at a time, entirely in compiled code.

Method (Madsen, Nielsen & Tingleff, *Methods for non-linear least squares problems*, 2004, sec. 3.2):
minimise E(q) = 1/2 |W e(q)|^2, with e the base-frame pose residual (p_d - p, log(R_d R^T)), the
position rows divided by the robot's size (unit-free) and W the 0/1 component mask. A step h solves
(J^T J + mu I) h = J^T e with J the geometric Jacobian [v; w] (for n >= 6 as J^T (J J^T + mu I)^-1 e,
the same step through a 6 x 6 system); it is accepted when E falls, and mu follows the gain ratio of
actual to predicted decrease (Nielsen's update).

Unit-free joint variables: the step is taken in radians for revolute joints and in robot sizes for
prismatic ones (J's prismatic columns multiplied by the robot's size, h's entries by it on the way
back). In length units the damping mu I would weigh a slide of one unit like a turn of one radian, so
the same robot solved far worse written in mm than in m (prismatic columns 1000x smaller, their steps
damped 1e6x more); now the iterations are the same in every unit.

Joint limits: a joint already on a limit and pushed past it is frozen for that step and the step is
solved again without it; the trial is then projected onto the limits (revolute joints whose range
spans a full turn are turned back by 2 pi instead, which changes no pose). The predicted decrease is
that of the step actually taken, so the gain ratio stays honest at the limits.

Attempts that are going nowhere restart from a random configuration within the limits (see
``kinematics.lm.LMSettings`` for the rules). The random numbers come from a splitmix64 stream seeded
per target (from one seed drawn from the caller's numpy Generator and the target's index), so a batch
gives each target the same answer as solving it alone with the same seed and index.

A batch is finished in the same loop, without the GIL and split over threads: each answer is turned by
whole turns into the limits nearest its preference and checked by an independent forward kinematics
(``pose_check.tool_errors``, the walk of ``Robot.fk``), so no per-target work is left to Python. The one
target's solver is ``lm_target.pxi``.
"""

cimport numpy as cnp
from libc.math cimport sqrt, fabs, ceil, isfinite, INFINITY, M_PI
from libc.stdlib cimport malloc, free
from libc.stdint cimport uint64_t
from cython.parallel cimport parallel, prange
from robkin.compiled.runtime.dense cimport cholesky_solve
from robkin.compiled.chain.fk cimport Chain, walk_tool
from robkin.compiled.chain.jacobian cimport jacobian_one
from robkin.compiled.runtime.linalg cimport rot_log
from robkin.compiled.ik.pose_check cimport tool_errors
from robkin.compiled.ik.subproblems cimport wrap_into_limits
from robkin.compiled.runtime.threads cimport batch_threads

import numpy as np

cnp.import_array()

cdef enum:
    # targets per thread before a batch is split: one target takes ~30-100 us
    MIN_TARGETS_PER_THREAD = 2

#: slack on "on a limit": a value clipped onto a limit may differ from it by a few ulps of 2 pi
#: (kinematics.limits.LIMIT_TOL, repeated here as a C constant)
cdef double LIMIT_TOL = 1e-12


include "lm_target.pxi"


cdef inline cnp.ndarray _doubles(object a, int ndim, Py_ssize_t d0, Py_ssize_t d1, Py_ssize_t d2, str what):
    """a as a C-contiguous float64 array of the given shape (d < 0: any length); ValueError if not.
    (Raw data pointers of such arrays cost far less than typed memoryviews per call.)"""
    cdef cnp.ndarray arr
    if cnp.PyArray_Check(a) and cnp.PyArray_TYPE(<cnp.ndarray>a) == cnp.NPY_DOUBLE \
            and cnp.PyArray_IS_C_CONTIGUOUS(<cnp.ndarray>a):
        arr = <cnp.ndarray>a        # the usual case, without numpy's conversion call (a single IK call
    else:                           # makes several of these)
        arr = np.ascontiguousarray(a, dtype=np.float64)
    cdef Py_ssize_t* want = [d0, d1, d2]
    cdef int i
    if cnp.PyArray_NDIM(arr) != ndim:
        raise ValueError(f"{what}: expected {ndim} dimensions")
    for i in range(ndim):
        if want[i] >= 0 and cnp.PyArray_DIM(arr, i) != want[i]:
            raise ValueError(f"{what}: unexpected shape {np.shape(arr)}")
    return arr


_ALPHA = {}


def _alpha(int n):
    """The R_d sequence's steps (n,) for n joints: phi^-1 .. phi^-n, phi the positive root of
    x^(n+1) = x + 1 (``robkin.samples``); computed once per n."""
    found = _ALPHA.get(n)
    if found is None:
        from robkin.samples import golden
        found = _ALPHA[n] = np.ascontiguousarray(1.0 / golden(n) ** np.arange(1, n + 1))
    return found


cdef struct Batch:
    # one batch's inputs and outputs, shared by every thread (each target writes only its own rows)
    const double* T         # (N, 16) targets
    const double* Q0        # first-attempt starts, row k at Q0 + q0_step * k
    const double* ref       # preferences for the turns of revolute joints, row k at ref + ref_step * k
    Py_ssize_t q0_step
    Py_ssize_t ref_step
    const double* lo
    const double* hi
    const double* rlo
    const double* rhi
    const unsigned char* wrap
    const double* w         # (6,) residual weights: the mask, position rows over the robot's size
    const double* msk       # (6,) the 0/1 mask itself (the check's residual, in length units)
    uint64_t seed
    double* Qo              # (N, n) answers
    unsigned char* ok       # (N,) verified
    long* its
    long* att
    double* ep
    double* eo


cdef inline void solve_target(Chain chain, const Params* P, const Batch* B, Py_ssize_t k,
                              double* work) noexcept nogil:
    """Target k of the batch, finished: solved (``solve_one``), its answer turned by whole turns into the
    limits nearest its preference, and checked by an independent forward kinematics (the walk of
    ``Robot.fk`` and the residual of ``pose_errors``): verified when within the tolerances over the
    masked components and every joint within its limits (up to LIMIT_TOL)."""
    cdef int n = P.n
    cdef double* q = B.Qo + n * k
    cdef const double* Td = B.T + 16 * k
    # one stream per target: seed and index mixed, so neighbouring targets get unrelated streams
    cdef uint64_t stream = B.seed ^ (<uint64_t>k * <uint64_t>0xD1B54A32D192ED03)
    solve_one(chain, P, B.w, B.lo, B.hi, B.wrap, B.rlo, B.rhi, Td, B.Q0 + B.q0_step * k, stream, work, q,
              B.its + k, B.att + k)
    cdef bint inside = wrap_into_limits(q, B.ref + B.ref_step * k, B.lo, B.hi, chain.rev, n, LIMIT_TOL)
    tool_errors(chain.L, chain.rev, n, q, Td, B.msk, B.ep + k, B.eo + k)
    B.ok[k] = inside and B.ep[k] <= P.tol_p and B.eo[k] <= P.tol_o


cdef inline cnp.ndarray _rows(object a, Py_ssize_t N, int n, str what, Py_ssize_t* step):
    """a as (N, n) or (1, n) float64 rows (one row serves every target: ``step`` 0, no copy of a
    broadcast preference)."""
    cdef cnp.ndarray arr = _doubles(a, 2, -1, n, 0, what)
    cdef Py_ssize_t rows = cnp.PyArray_DIM(arr, 0)
    if rows != N and rows != 1:
        raise ValueError(f"{what}: expected {N} or 1 rows, got {rows}")
    step[0] = n if rows == N else 0
    return arr


def solve(Chain chain, targets, q0, mask, lower, upper, restart_lower, restart_upper, double scale,
          settings, uint64_t seed, int threads=0, ref=None):
    """Solve every target (N, 4, 4) from its start q0 (N, n) or (1, n); see ``kinematics.lm.solve_lm``.

    Each answer is turned by whole turns into the limits nearest ``ref`` (N, n) or (1, n) (default q0)
    and checked by forward kinematics, all in the compiled loop. Returns q (N, n), verified (N,) bool,
    iterations (N,) int64, attempts (N,) int64, position and orientation errors (N,) (length units,
    radians, over the masked components). The targets are split over ``threads`` (0: automatic, see
    ``threads.pyx``; one thread runs without entering an OpenMP region); each target's random restarts
    come from its own stream (seed and index), so the results do not depend on the thread count.
    """
    cdef int n = chain.n
    cdef cnp.ndarray Ta = _doubles(targets, 3, -1, 4, 4, "targets")
    cdef Py_ssize_t N = cnp.PyArray_DIM(Ta, 0), k, q0_step, ref_step
    cdef cnp.ndarray Q0a = _rows(q0, N, n, "q0", &q0_step)
    cdef cnp.ndarray Ra = Q0a if ref is None else _rows(ref, N, n, "ref", &ref_step)
    if ref is None:
        ref_step = q0_step
    cdef cnp.ndarray loa = _doubles(lower, 1, n, 0, 0, "lower")
    cdef cnp.ndarray hia = _doubles(upper, 1, n, 0, 0, "upper")
    cdef cnp.ndarray rloa = _doubles(restart_lower, 1, n, 0, 0, "restart_lower")
    cdef cnp.ndarray rhia = _doubles(restart_upper, 1, n, 0, 0, "restart_upper")
    cdef cnp.ndarray ma = _doubles(mask, 1, 6, 0, 0, "mask")
    cdef Batch B
    cdef Params P
    P.n = n
    P.max_iter = settings.max_iterations
    P.restarts = settings.restarts
    P.stall_window = settings.stall_window
    P.check_iteration = settings.check_iteration
    P.limit_check_iteration = settings.limit_check_iteration
    P.tol_p = settings.tol_position
    P.tol_o = settings.tol_orientation
    P.tau = settings.tau
    P.mu_stuck = settings.mu_stuck
    P.stall_ratio = settings.stall_ratio
    P.check_E = settings.check_E
    P.limit_check_E = settings.limit_check_E
    P.scale = scale
    P.limited = False
    if P.stall_window < 1:
        raise ValueError("stall_window must be >= 1")
    B.T = <const double*>cnp.PyArray_DATA(Ta)
    B.Q0 = <const double*>cnp.PyArray_DATA(Q0a)
    B.ref = <const double*>cnp.PyArray_DATA(Ra)
    B.q0_step, B.ref_step = q0_step, ref_step
    B.lo = <const double*>cnp.PyArray_DATA(loa)
    B.hi = <const double*>cnp.PyArray_DATA(hia)
    B.rlo = <const double*>cnp.PyArray_DATA(rloa)
    B.rhi = <const double*>cnp.PyArray_DATA(rhia)
    B.msk = <const double*>cnp.PyArray_DATA(ma)
    B.seed = seed
    cdef unsigned char* wrap = <unsigned char*>malloc(n * sizeof(unsigned char))
    cdef double* work = NULL      # each thread's own (allocated in the parallel block)
    cdef Py_ssize_t work_size = 25 * n + 6 + P.stall_window
    cdef int nt = batch_threads(threads, N, MIN_TARGETS_PER_THREAD), failed = 0
    if wrap == NULL:
        raise MemoryError()
    cdef int j
    for j in range(n):
        if isfinite(B.lo[j]) or isfinite(B.hi[j]):
            P.limited = True
        # revolute joints whose range spans a full turn: a value past a limit is turned back by 2 pi
        wrap[j] = chain.rev[j] and B.hi[j] - B.lo[j] >= 2.0 * M_PI
    B.wrap = wrap
    alpha = _alpha(n)
    P.alpha = <const double*>cnp.PyArray_DATA(alpha)
    cdef double w[6]
    for j in range(6):
        w[j] = B.msk[j] / scale if j < 3 else B.msk[j]
    B.w = w
    cdef cnp.npy_intp dims[2]
    dims[0] = N
    dims[1] = n
    cdef cnp.ndarray q_arr = cnp.PyArray_EMPTY(2, dims, cnp.NPY_DOUBLE, 0)
    cdef cnp.ndarray ok_arr = cnp.PyArray_ZEROS(1, dims, cnp.NPY_BOOL, 0)
    cdef cnp.ndarray it_arr = cnp.PyArray_ZEROS(1, dims, cnp.NPY_INT64, 0)
    cdef cnp.ndarray at_arr = cnp.PyArray_ZEROS(1, dims, cnp.NPY_INT64, 0)
    cdef cnp.ndarray ep_arr = cnp.PyArray_EMPTY(1, dims, cnp.NPY_DOUBLE, 0)
    cdef cnp.ndarray eo_arr = cnp.PyArray_EMPTY(1, dims, cnp.NPY_DOUBLE, 0)
    B.Qo = <double*>cnp.PyArray_DATA(q_arr)
    B.ok = <unsigned char*>cnp.PyArray_DATA(ok_arr)
    B.its = <long*>cnp.PyArray_DATA(it_arr)
    B.att = <long*>cnp.PyArray_DATA(at_arr)
    B.ep = <double*>cnp.PyArray_DATA(ep_arr)
    B.eo = <double*>cnp.PyArray_DATA(eo_arr)
    if nt <= 1:
        # no OpenMP region: entering one costs ~0.5 us, a tenth of an easy single target's solve
        work = <double*>malloc(work_size * sizeof(double))
        if work != NULL:
            with nogil:
                for k in range(N):
                    solve_target(chain, &P, &B, k, work)
        failed = work == NULL
        free(work)
    else:
        with nogil, parallel(num_threads=nt):
            work = <double*>malloc(work_size * sizeof(double))
            # dynamic schedule: a target's time varies (restarts), so threads take the next one when free
            for k in prange(N, schedule="dynamic", chunksize=1):
                if work == NULL:
                    failed += 1   # a reduction: any thread that ran out of memory counts
                    continue
                solve_target(chain, &P, &B, k, work)
            free(work)
    free(wrap)
    if failed:
        raise MemoryError()
    return q_arr, ok_arr, it_arr, at_arr, ep_arr, eo_arr


def pose_errors(Chain chain, q, targets, mask):
    """Masked position and orientation errors of the tool at q (M, n) towards targets (M, 4, 4).

    Forward kinematics (the same walk as ``Robot.fk``) and the residual (p_d - p, log(R_d R^T)) over
    the components the 0/1 ``mask`` (6,) selects. Returns ep, eo (M,): length units and radians,
    inf where a row of q is not finite.
    """
    cdef int n = chain.n
    cdef cnp.ndarray Qa = _doubles(q, 2, -1, n, 0, "q")
    cdef Py_ssize_t M = cnp.PyArray_DIM(Qa, 0), k
    cdef cnp.ndarray Ta = _doubles(targets, 3, M, 4, 4, "targets")
    cdef cnp.ndarray ma = _doubles(mask, 1, 6, 0, 0, "mask")
    cdef const double* Q = <const double*>cnp.PyArray_DATA(Qa)
    cdef const double* Td = <const double*>cnp.PyArray_DATA(Ta)
    cdef const double* msk = <const double*>cnp.PyArray_DATA(ma)
    cdef cnp.npy_intp dims[1]
    dims[0] = M
    cdef cnp.ndarray ep_arr = cnp.PyArray_EMPTY(1, dims, cnp.NPY_DOUBLE, 0)
    cdef cnp.ndarray eo_arr = cnp.PyArray_EMPTY(1, dims, cnp.NPY_DOUBLE, 0)
    cdef double* ep = <double*>cnp.PyArray_DATA(ep_arr)
    cdef double* eo = <double*>cnp.PyArray_DATA(eo_arr)
    with nogil:
        for k in range(M):
            tool_errors(chain.L, chain.rev, n, Q + n * k, Td + 16 * k, msk, ep + k, eo + k)
    return ep_arr, eo_arr
