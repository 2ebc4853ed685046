# cython: language_level=3
"""Nonlinear least squares with box bounds for small dense problems: Levenberg-Marquardt, compiled.

Method (Madsen, Nielsen & Tingleff, *Methods for non-linear least squares problems*, 2004, sec. 3.2,
with the bounds handled by projection): minimise F(x) = 1/2 |r(x)|^2 subject to lo <= x <= hi. A step
h solves (J^T J + mu D) h = -J^T r on the free variables (those not held on a bound by the gradient);
D is Marquardt's diagonal scaling as in MINPACK (the largest
diagonal of J^T J seen so far), which makes the steps independent of the variables' units; the trial
x + h is projected onto the box, and the decrease the linear model predicts for the step
actually taken decides, through the gain ratio, whether it is accepted and how mu changes (Nielsen's
update). The stopping tests follow ``scipy.optimize.least_squares``: the cost falls by less than
``ftol`` relative in a good step, the step is below ``xtol`` relative to x, the projected gradient's
largest entry is below ``gtol``; and, for zero-residual problems, |r| <= ``rtol``.

Why by hand: the synthesis optimiser solves problems of ~20-40 variables and residuals thousands of
times. scipy's ``least_squares`` (trust-region reflective) gets the same optima, but importing
``scipy.optimize`` costs ~0.7 s and each iteration's SVD and bookkeeping ~0.5 ms, more than the
residuals themselves; no well-kept library offers a bounded dense LM without that overhead. The
Cholesky solve is the one the inverse-kinematics LM uses (``dense.pxd``).

The residual and Jacobian come from Python callables, ``fun(x) -> (m,)`` and ``jac(x) -> (m, n)``.
"""

cimport numpy as cnp
from libc.math cimport sqrt, fabs, isfinite
from libc.stdlib cimport malloc, free
from robkin.compiled.runtime.dense cimport cholesky_solve

import numpy as np

cnp.import_array()

#: ``solve``'s status codes (> 0: a tolerance was met; 0: the evaluation limit)
MESSAGES = {
    0: "the evaluation limit was reached",
    1: "the projected gradient is below gtol",
    2: "the cost changed by less than ftol",
    3: "the step is below xtol",
    4: "the residual is below rtol",
}

#: Initial damping mu, relative to the diagonal of J^T J (Madsen et al. recommend 1e-6 for a good
#: start, up to 1 for a poor one). 1e-1 by measurement: on the synthesis benchmark (25 tasks each of
#: 3 and 4 poses, cost 'manipulability') the best of 8 starts was cheaper than with 1e-3 on 31 of 50
#: tasks, and cheaper than scipy's trust-region reflective on 29 (ties on 3).
cdef double TAU = 1e-1
#: Relative damping beyond this means no step can be made: every step would be ~1e30 times shorter
#: than a Gauss-Newton step along the same direction, far below the resolution of any iterate.
cdef double MU_LIMIT = 1e30


cdef inline double half_sq(const double[::1] r) noexcept nogil:
    cdef Py_ssize_t i
    cdef double s = 0.0
    for i in range(r.shape[0]):
        s += r[i] * r[i]
    return 0.5 * s


cdef inline void normal_equations(const double[:, ::1] J, const double[::1] r, double* A, double* g) noexcept nogil:
    """A = J^T J (n x n, full), g = J^T r (n)."""
    cdef Py_ssize_t m = J.shape[0], n = J.shape[1], i, j, k
    cdef double s
    for i in range(n):
        s = 0.0
        for k in range(m):
            s += J[k, i] * r[k]
        g[i] = s
        for j in range(i + 1):
            s = 0.0
            for k in range(m):
                s += J[k, i] * J[k, j]
            A[i * n + j] = s
            A[j * n + i] = s


def _residual(fun, cnp.ndarray x, Py_ssize_t m, str what):
    r = np.ascontiguousarray(fun(x.copy()), dtype=np.float64)
    if r.ndim != 1 or (m >= 0 and r.shape[0] != m):
        raise ValueError(f"box_lsq.solve: {what} returned shape {r.shape}, expected ({m if m >= 0 else 'm'},)")
    return r


def _jacobian(jac, cnp.ndarray x, Py_ssize_t m, Py_ssize_t n):
    J = np.ascontiguousarray(jac(x.copy()), dtype=np.float64)
    if J.shape != (m, n):
        raise ValueError(f"box_lsq.solve: jac returned shape {J.shape}, expected ({m}, {n})")
    return J


def solve(fun, jac, x0, lower, upper, double ftol=0.0, double xtol=0.0, double gtol=0.0,
          double rtol=0.0, int max_nfev=1000):
    """Minimise 1/2 |fun(x)|^2 over lower <= x <= upper from x0.

    Parameters
    ----------
    fun : callable, (n,) -> (m,)
        Residuals. Non-finite values reject the trial step.
    jac : callable, (n,) -> (m, n)
        Their Jacobian.
    x0, lower, upper : (n,) arrays
        Start (projected onto the box) and bounds (lower <= upper; +-inf allowed).
    ftol, xtol, gtol, rtol : float
        Stopping tolerances (0 disables one): relative cost decrease of a good step (gain ratio > 1/4),
        step length relative to xtol + |x|, largest projected-gradient entry, residual norm.
    max_nfev : int
        Limit of residual evaluations.

    Returns
    -------
    x : (n,) array
    cost : float
        1/2 |fun(x)|^2.
    nfev, njev : int
        Residual and Jacobian evaluations.
    status : int
        Key of ``MESSAGES``: 1-4 a tolerance was met, 0 the evaluation limit.
    """
    cdef cnp.ndarray lo_a = np.ascontiguousarray(lower, dtype=np.float64).ravel()
    cdef cnp.ndarray hi_a = np.ascontiguousarray(upper, dtype=np.float64).ravel()
    cdef cnp.ndarray x_a = np.clip(np.asarray(x0, dtype=np.float64).ravel(), lo_a, hi_a)
    cdef Py_ssize_t n = x_a.shape[0], m, i, j, nf
    if lo_a.shape[0] != n or hi_a.shape[0] != n or not np.all(lo_a <= hi_a):
        raise ValueError("box_lsq.solve: expected lower <= upper, both of x0's length")
    if not np.all(np.isfinite(x_a)):
        raise ValueError("box_lsq.solve: x0 must be finite")
    cdef const double[::1] lo = lo_a
    cdef const double[::1] hi = hi_a
    cdef double[::1] x = x_a
    cdef cnp.ndarray xt_a = np.empty(n)
    cdef double[::1] xt = xt_a
    r_a = _residual(fun, x_a, -1, "fun")
    m = r_a.shape[0]
    if not np.all(np.isfinite(r_a)):
        raise ValueError("box_lsq.solve: fun is not finite at x0")
    cdef double[::1] r = r_a
    cdef double[::1] rt
    cdef const double[:, ::1] J = _jacobian(jac, x_a, m, n)
    cdef int nfev = 1, njev = 1, status = 0
    cdef double F = half_sq(r), Ft, mu, nu = 2.0, pred, rho, s, hn, xn, g_max, diag_max = 0.0
    cdef double* A = <double*>malloc(n * n * sizeof(double))
    cdef double* Af = <double*>malloc(n * n * sizeof(double))
    cdef double* g = <double*>malloc(n * sizeof(double))
    cdef double* h = <double*>malloc(n * sizeof(double))
    cdef int* free_idx = <int*>malloc(n * sizeof(int))
    cdef double* D = <double*>malloc(n * sizeof(double))
    if A == NULL or Af == NULL or g == NULL or h == NULL or free_idx == NULL or D == NULL:
        free(A); free(Af); free(g); free(h); free(free_idx); free(D)
        raise MemoryError()
    try:
        normal_equations(J, r, A, g)
        for i in range(n):
            diag_max = max(diag_max, A[i * n + i])
        # Marquardt's scaling as in MINPACK (More 1978): damping mu D with D the largest diagonal of
        # J^T J seen so far, so the step does not depend on the variables' units. The floor (1e-12 of
        # the largest entry) keeps a variable the residuals do not yet depend on movable.
        for i in range(n):
            D[i] = max(A[i * n + i], 1e-12 * diag_max)
        mu = TAU
        while True:
            if sqrt(2.0 * F) <= rtol:
                status = 4
                break
            # free variables: those a descent step (-g) would not push out of the box
            nf = 0
            g_max = 0.0
            for i in range(n):
                if (x[i] <= lo[i] and g[i] > 0.0) or (x[i] >= hi[i] and g[i] < 0.0):
                    continue
                free_idx[nf] = <int>i
                nf += 1
                g_max = max(g_max, fabs(g[i]))
            if g_max <= gtol:
                status = 1
                break
            if nfev >= max_nfev:
                status = 0
                break
            for i in range(nf):
                for j in range(nf):
                    Af[i * nf + j] = A[free_idx[i] * n + free_idx[j]]
                Af[i * nf + i] += mu * D[free_idx[i]]
                h[i] = -g[free_idx[i]]
            if not cholesky_solve(Af, h, <int>nf):
                mu *= nu          # not definite to rounding (J^T J singular, mu tiny): damp more
                nu *= 2.0
                if mu > MU_LIMIT:
                    status = 3
                    break
                continue
            for i in range(n):
                xt[i] = x[i]
            for j in range(nf):
                i = free_idx[j]
                xt[i] = min(max(x[i] + h[j], lo[i]), hi[i])
            # the step actually taken, its length and the decrease the linear model predicts for it
            hn = 0.0
            xn = 0.0
            pred = 0.0
            for i in range(n):
                h[i] = xt[i] - x[i]
                hn += h[i] * h[i]
                xn += x[i] * x[i]
                pred -= g[i] * h[i]
            for i in range(n):
                s = 0.0
                for j in range(n):
                    s += A[i * n + j] * h[j]
                pred -= 0.5 * h[i] * s
            hn = sqrt(hn)
            if hn <= xtol * (xtol + sqrt(xn)):
                status = 3
                break
            rt_a = _residual(fun, xt_a, m, "fun")
            rt = rt_a
            nfev += 1
            Ft = half_sq(rt)
            if isfinite(Ft) and Ft < F and pred > 0.0:
                rho = (F - Ft) / pred
                if F - Ft < ftol * F and rho > 0.25:
                    status = 2
                for i in range(n):
                    x[i] = xt[i]
                r_a = rt_a
                r = rt
                F = Ft
                if status == 2:
                    break
                J = _jacobian(jac, x_a, m, n)
                njev += 1
                normal_equations(J, r, A, g)
                for i in range(n):
                    D[i] = max(D[i], A[i * n + i])
                s = 2.0 * rho - 1.0
                mu *= max(1.0 / 3.0, 1.0 - s * s * s)
                nu = 2.0
            else:
                mu *= nu
                nu *= 2.0
                if mu > MU_LIMIT:
                    status = 3
                    break
    finally:
        free(A); free(Af); free(g); free(h); free(free_idx); free(D)
    return x_a, F, nfev, njev, status
