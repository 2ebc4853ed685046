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
"""

cimport numpy as cnp
from libc.math cimport sqrt, fabs, ceil, isfinite, INFINITY, M_PI
from libc.stdlib cimport malloc, free
from libc.stdint cimport uint64_t
from cython.parallel cimport parallel, prange
from robkin.compiled.dense cimport cholesky_solve
from robkin.compiled.fk cimport Chain, walk_tool
from robkin.compiled.jacobian cimport jacobian_one
from robkin.compiled.linalg cimport rot_log
from robkin.compiled.pose_check cimport tool_errors
from robkin.compiled.threads cimport batch_threads

import numpy as np

cnp.import_array()

cdef enum:
    # targets per thread before a batch is split: one target takes ~30-100 us
    MIN_TARGETS_PER_THREAD = 2

#: slack on "on a limit": a value clipped onto a limit may differ from it by a few ulps of 2 pi
#: (kinematics.limits.LIMIT_TOL, repeated here as a C constant)
cdef double LIMIT_TOL = 1e-12


cdef struct Params:
    int n
    int max_iter
    int restarts
    int stall_window
    int check_iteration
    int limit_check_iteration
    double tol_p
    double tol_o
    double tau
    double mu_stuck
    double stall_ratio
    double check_E
    double limit_check_E
    double scale
    bint limited
    const double* alpha     # (n,) the R_d sequence's step per joint (restart starts)


cdef inline uint64_t splitmix64(uint64_t* state) noexcept nogil:
    """Next value of the splitmix64 stream (Steele, Lea & Flood 2014): 64 well-mixed bits."""
    cdef uint64_t z
    state[0] += <uint64_t>0x9E3779B97F4A7C15
    z = state[0]
    z = (z ^ (z >> 30)) * <uint64_t>0xBF58476D1CE4E5B9
    z = (z ^ (z >> 27)) * <uint64_t>0x94D049BB133111EB
    return z ^ (z >> 31)


cdef inline double uniform01(uint64_t* state) noexcept nogil:
    """Uniform double in [0, 1) from the top 53 bits."""
    return <double>(splitmix64(state) >> 11) * (1.0 / 9007199254740992.0)


cdef inline void damped_step(const double* J, const double* e, double mu, int n, double* h) noexcept nogil:
    """h (n) = (J^T J + mu I)^-1 J^T e for J (6 x n): through the 6 x 6 system J J^T + mu I when
    n >= 6 (push-through identity), else through the n x n one. mu > 0 keeps both definite."""
    cdef double A[36]
    cdef double y[6]
    cdef int i, j, k
    cdef double s
    if n >= 6:
        for i in range(6):
            for j in range(i + 1):
                s = 0.0
                for k in range(n):
                    s += J[i * n + k] * J[j * n + k]
                A[i * 6 + j] = s
            A[i * 6 + i] += mu
            y[i] = e[i]
        if not cholesky_solve(A, y, 6):
            for k in range(n):
                h[k] = 0.0
            return
        for k in range(n):
            s = 0.0
            for i in range(6):
                s += J[i * n + k] * y[i]
            h[k] = s
        return
    for i in range(n):
        for j in range(i + 1):
            s = 0.0
            for k in range(6):
                s += J[k * n + i] * J[k * n + j]
            A[i * n + j] = s
        A[i * n + i] += mu
        s = 0.0
        for k in range(6):
            s += J[k * n + i] * e[k]
        h[i] = s
    if not cholesky_solve(A, h, n):
        for k in range(n):
            h[k] = 0.0


cdef inline double joint_unit(Chain chain, const Params* P, int j) noexcept nogil:
    """The unit of joint j's step (module doc): 1 rad for a revolute joint, the robot's size for a
    prismatic one."""
    return 1.0 if chain.rev[j] else P.scale


cdef inline double evaluate(Chain chain, const Params* P, const double* w, const double* Td,
                            const double* q, double* e, double* J) noexcept nogil:
    """Weighted residual e (6) and Jacobian J (6 x n, per unit-free joint step) at q; returns
    E = |e|^2 / 2."""
    cdef double T[16]
    cdef double M[9]
    cdef int i, j, n = P.n
    jacobian_one(chain.L, chain.rev, n, q, 0, J, T)
    e[0] = Td[3] - T[3]
    e[1] = Td[7] - T[7]
    e[2] = Td[11] - T[11]
    # M = R_d R^T
    for i in range(3):
        for j in range(3):
            M[3 * i + j] = Td[4 * i] * T[4 * j] + Td[4 * i + 1] * T[4 * j + 1] + Td[4 * i + 2] * T[4 * j + 2]
    rot_log(M, e + 3)
    for i in range(6):
        e[i] *= w[i]
        for j in range(n):
            J[i * n + j] *= w[i] * joint_unit(chain, P, j)
    return 0.5 * (e[0] * e[0] + e[1] * e[1] + e[2] * e[2] + e[3] * e[3] + e[4] * e[4] + e[5] * e[5])


cdef inline bint converged(const Params* P, const double* e) noexcept nogil:
    # e is weighted: position rows are in units of the robot's size. Half the tolerance: the caller
    # re-checks with Robot.fk, whose rounding (~1e-15 relative) must not flip a verdict.
    cdef double ep = sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]) * P.scale
    cdef double eo = sqrt(e[3] * e[3] + e[4] * e[4] + e[5] * e[5])
    return ep <= 0.5 * P.tol_p and eo <= 0.5 * P.tol_o


cdef bint solve_one(Chain chain, const Params* P, const double* w, const double* lo, const double* hi,
                    const unsigned char* wrap, const double* rlo, const double* rhi, const double* Td,
                    const double* q0, uint64_t seed, double* work, double* q_out, long* iterations,
                    long* attempts) noexcept nogil:
    """One target: attempts from q0 (clipped into the limits), then random restarts, until converged.

    q_out receives the converged configuration, or the best one found (smallest E). ``work`` holds
    24 n + 6 + stall_window doubles.
    """
    cdef int n = P.n, i, j, it, attempt, slot
    cdef double* q = work
    cdef double* qt = q + n
    cdef double* h = qt + n
    cdef double* hb = h + n
    cdef double* best_q = hb + n
    cdef double* Jh = best_q + n          # 6 used
    cdef double* blocked = Jh + 6         # n used, 0/1
    cdef double* J = blocked + n
    cdef double* Jt = J + 6 * n
    cdef double* Jb = Jt + 6 * n
    cdef double* Ewin = Jb + 6 * n
    cdef double* shift = Ewin + P.stall_window   # n used: this target's random shift of the R_d sequence
    cdef double e[6]
    cdef double et[6]
    cdef double E, Et, mu, nu, diag, diag_max, predicted, actual, rho, x, before, two_pi = 2.0 * M_PI
    cdef double best_E = INFINITY
    cdef bint stalled, stuck, hasty, any_blocked, at_limit, accept
    cdef uint64_t state = seed
    cdef long total_it = 0
    cdef double* swap
    for attempt in range(P.restarts + 1):
        attempts[0] = attempt + 1
        for j in range(n):
            if attempt == 0:
                x = q0[j]
                q[j] = lo[j] if x < lo[j] else (hi[j] if x > hi[j] else x)
                best_q[j] = q[j]      # defined even if no attempt ever has a finite E
            else:
                # restarts walk the R_d sequence (Roberts' additive recurrence, see robkin.samples), shifted
                # by a random offset per target: successive starts spread evenly over the whole box of
                # the limits, its corners and edges included, where uniform draws leave gaps and clumps
                if attempt == 1:
                    shift[j] = uniform01(&state)
                x = shift[j] + attempt * P.alpha[j]
                x -= <double>(<long>x)
                q[j] = rlo[j] + (rhi[j] - rlo[j]) * x
        E = evaluate(chain, P, w, Td, q, e, J)
        # largest diagonal entry of J^T J; the floor keeps the damping positive for a zero Jacobian
        diag_max = 1e-12
        for j in range(n):
            diag = 0.0
            for i in range(6):
                diag += J[i * n + j] * J[i * n + j]
            if diag > diag_max:
                diag_max = diag
        mu = P.tau * diag_max
        nu = 2.0
        for i in range(P.stall_window):
            Ewin[i] = INFINITY
        Ewin[0] = E
        stalled = False
        # the early give-up rules apply while a target has used at most half its attempts: after that
        # every attempt runs its full course (geometries where convergence is slower than on the arms
        # the rules were tuned on, e.g. long prismatic travel)
        hasty = attempt + 1 <= (P.restarts + 1) // 2
        it = 0
        while True:
            if converged(P, e):
                for j in range(n):
                    q_out[j] = q[j]
                iterations[0] = total_it + it
                return True
            stuck = it >= P.max_iter or stalled or mu > P.mu_stuck * diag_max \
                or (hasty and it >= P.check_iteration and E > P.check_E)
            if not stuck and P.limited and hasty and it == P.limit_check_iteration and E > P.limit_check_E:
                for j in range(n):
                    if q[j] <= lo[j] + LIMIT_TOL or q[j] >= hi[j] - LIMIT_TOL:
                        stuck = True
                        break
            if stuck:
                total_it += it
                if E < best_E:
                    best_E = E
                    for j in range(n):
                        best_q[j] = q[j]
                break
            # --- one damped Gauss-Newton step
            damped_step(J, e, mu, n, h)
            if P.limited:
                # joints already on a limit and pushed past it are frozen for this step and the step
                # is solved again without them, so the others keep making progress along the limit
                any_blocked = False
                for j in range(n):
                    x = q[j] + h[j] * joint_unit(chain, P, j)
                    at_limit = (x < lo[j] and q[j] <= lo[j] + LIMIT_TOL) or (x > hi[j] and q[j] >= hi[j] - LIMIT_TOL)
                    blocked[j] = 1.0 if at_limit else 0.0
                    any_blocked = any_blocked or at_limit
                if any_blocked:
                    for i in range(6):
                        for j in range(n):
                            Jb[i * n + j] = 0.0 if blocked[j] != 0.0 else J[i * n + j]
                    damped_step(Jb, e, mu, n, hb)
                    for j in range(n):
                        h[j] = 0.0 if blocked[j] != 0.0 else hb[j]
                for j in range(n):
                    x = q[j] + h[j] * joint_unit(chain, P, j)
                    if wrap[j]:
                        if x > hi[j]:
                            x -= two_pi * ceil((x - hi[j]) / two_pi)
                        elif x < lo[j]:
                            x += two_pi * ceil((lo[j] - x) / two_pi)
                    x = lo[j] if x < lo[j] else (hi[j] if x > hi[j] else x)
                    qt[j] = x
                    # the step actually taken, before whole turns (which change no pose) are taken off
                    if not wrap[j]:
                        h[j] = (x - q[j]) / joint_unit(chain, P, j)
            else:
                for j in range(n):
                    qt[j] = q[j] + h[j] * joint_unit(chain, P, j)
            predicted = 0.0
            x = 0.0
            for i in range(6):
                Jh[i] = 0.0
                for j in range(n):
                    Jh[i] += J[i * n + j] * h[j]
                predicted += e[i] * Jh[i]
                x += Jh[i] * Jh[i]
            predicted -= 0.5 * x
            Et = evaluate(chain, P, w, Td, qt, et, Jt)
            actual = E - Et
            accept = actual > 0.0 and predicted > 0.0
            # Nielsen's damping update: shrink by up to 3 on a good step, grow geometrically on a bad
            # one; floor: relative damping below 1e-12 changes no step measurably, and keeps J^T J + mu I
            # (singular for a redundant arm) safely invertible (condition number <= 1e12)
            if accept:
                rho = actual / predicted
                x = 1.0 - (2.0 * rho - 1.0) ** 3
                mu *= x if x > 1.0 / 3.0 else 1.0 / 3.0
                nu = 2.0
                swap = q
                q = qt
                qt = swap
                swap = J
                J = Jt
                Jt = swap
                for i in range(6):
                    e[i] = et[i]
                E = Et
            else:
                mu *= nu
                nu *= 2.0
            if mu < 1e-12 * diag_max:
                mu = 1e-12 * diag_max
            # stall test: E now against E stall_window iterations ago (a ring buffer, inf-filled)
            it += 1
            slot = it % P.stall_window
            before = Ewin[slot]
            Ewin[slot] = E
            stalled = E > (1.0 - P.stall_ratio) * before
    for j in range(n):
        q_out[j] = best_q[j]
    iterations[0] = total_it
    return False


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


def solve(Chain chain, targets, q0, mask, lower, upper, restart_lower, restart_upper, double scale,
          settings, uint64_t seed, int threads=0):
    """Solve every target (N, 4, 4) from its start q0 (N, n); see ``kinematics.lm.solve_lm``.

    Returns q (N, n), converged (N,) bool, iterations (N,) int64, attempts (N,) int64. The targets are
    split over ``threads`` (0: automatic, see ``threads.pyx``); each target's random restarts come from
    its own stream (seed and index), so the results do not depend on the thread count.
    """
    cdef int n = chain.n
    cdef cnp.ndarray Ta = _doubles(targets, 3, -1, 4, 4, "targets")
    cdef Py_ssize_t N = cnp.PyArray_DIM(Ta, 0), k
    cdef cnp.ndarray Q0a = _doubles(q0, 2, N, n, 0, "q0")
    cdef cnp.ndarray loa = _doubles(lower, 1, n, 0, 0, "lower")
    cdef cnp.ndarray hia = _doubles(upper, 1, n, 0, 0, "upper")
    cdef cnp.ndarray rloa = _doubles(restart_lower, 1, n, 0, 0, "restart_lower")
    cdef cnp.ndarray rhia = _doubles(restart_upper, 1, n, 0, 0, "restart_upper")
    cdef cnp.ndarray ma = _doubles(mask, 1, 6, 0, 0, "mask")
    cdef const double* T = <const double*>cnp.PyArray_DATA(Ta)
    cdef const double* Q0 = <const double*>cnp.PyArray_DATA(Q0a)
    cdef const double* lo = <const double*>cnp.PyArray_DATA(loa)
    cdef const double* hi = <const double*>cnp.PyArray_DATA(hia)
    cdef const double* rlo = <const double*>cnp.PyArray_DATA(rloa)
    cdef const double* rhi = <const double*>cnp.PyArray_DATA(rhia)
    cdef const double* msk = <const double*>cnp.PyArray_DATA(ma)
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
    cdef unsigned char* wrap = <unsigned char*>malloc(n * sizeof(unsigned char))
    cdef double* work = NULL      # each thread's own (allocated in the parallel block)
    cdef Py_ssize_t work_size = 25 * n + 6 + P.stall_window
    cdef int nt = batch_threads(threads, N, MIN_TARGETS_PER_THREAD), failed = 0
    if wrap == NULL:
        raise MemoryError()
    cdef int j
    for j in range(n):
        if isfinite(lo[j]) or isfinite(hi[j]):
            P.limited = True
        # revolute joints whose range spans a full turn: a value past a limit is turned back by 2 pi
        wrap[j] = chain.rev[j] and hi[j] - lo[j] >= 2.0 * M_PI
    alpha = _alpha(n)
    P.alpha = <const double*>cnp.PyArray_DATA(alpha)
    cdef double w[6]
    for j in range(6):
        w[j] = msk[j] / scale if j < 3 else msk[j]
    cdef cnp.npy_intp dims[2]
    dims[0] = N
    dims[1] = n
    cdef cnp.ndarray q_arr = cnp.PyArray_EMPTY(2, dims, cnp.NPY_DOUBLE, 0)
    cdef cnp.ndarray ok_arr = cnp.PyArray_ZEROS(1, dims, cnp.NPY_BOOL, 0)
    cdef cnp.ndarray it_arr = cnp.PyArray_ZEROS(1, dims, cnp.NPY_INT64, 0)
    cdef cnp.ndarray at_arr = cnp.PyArray_ZEROS(1, dims, cnp.NPY_INT64, 0)
    cdef double* Qo = <double*>cnp.PyArray_DATA(q_arr)
    cdef unsigned char* ok = <unsigned char*>cnp.PyArray_DATA(ok_arr)
    cdef long* its = <long*>cnp.PyArray_DATA(it_arr)
    cdef long* att = <long*>cnp.PyArray_DATA(at_arr)
    cdef uint64_t stream
    with nogil, parallel(num_threads=nt):
        work = <double*>malloc(work_size * sizeof(double))
        # dynamic schedule: a target's time varies (restarts), so threads take the next one when free
        for k in prange(N, schedule="dynamic", chunksize=1):
            if work == NULL:
                failed += 1   # a reduction: any thread that ran out of memory counts
                continue
            # one stream per target: seed and index mixed, so neighbouring targets get unrelated streams
            stream = seed ^ (<uint64_t>k * <uint64_t>0xD1B54A32D192ED03)
            ok[k] = solve_one(chain, &P, w, lo, hi, wrap, rlo, rhi, T + 16 * k, Q0 + n * k, stream, work,
                              Qo + n * k, its + k, att + k)
        free(work)
    free(wrap)
    if failed:
        raise MemoryError()
    return q_arr, ok_arr, it_arr, at_arr


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
