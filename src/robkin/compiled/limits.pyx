# cython: language_level=3
"""Joint-limit bookkeeping for solutions: whole turns of revolute joints into the limits, and the
check that every joint lies within them (the kernels behind ``kinematics.limits``)."""

from libc.math cimport ceil, floor, rint, M_PI

import numpy as np

#: slack on limit checks (``kinematics.limits.LIMIT_TOL``; passed in, so there is one definition)


def wrap(Q, lower, upper, revolute, ref, double tol):
    """Revolute values of Q (M, n) shifted by whole turns into [lower, upper], nearest to ref (M, n).

    Returns the shifted copy (M, n) and ok (M,) bool: every joint within its limits up to ``tol``.
    Prismatic joints are only checked. Where no turn fits, the turn nearest the range is taken (and ok
    is False), as ``numpy.clip`` with crossed bounds would.
    """
    cdef const double[:, ::1] q = np.ascontiguousarray(Q, dtype=np.float64)
    cdef const double[:, ::1] r = np.ascontiguousarray(ref, dtype=np.float64)
    cdef const double[::1] lo = np.ascontiguousarray(lower, dtype=np.float64)
    cdef const double[::1] hi = np.ascontiguousarray(upper, dtype=np.float64)
    cdef const unsigned char[::1] rev = np.ascontiguousarray(revolute, dtype=np.uint8)
    cdef Py_ssize_t M = q.shape[0], n = q.shape[1], i, j
    if r.shape[0] != M or r.shape[1] != n or lo.shape[0] != n or hi.shape[0] != n or rev.shape[0] != n:
        raise ValueError("wrap: expected Q and ref (M, n), lower, upper, revolute (n,)")
    out_arr = np.empty((M, n))
    ok_arr = np.ones(M, np.uint8)
    cdef double[:, ::1] out = out_arr
    cdef unsigned char[::1] ok = ok_arr
    cdef double two_pi = 2.0 * M_PI, x, k, k_lo, k_hi
    with nogil:
        for i in range(M):
            for j in range(n):
                x = q[i, j]
                if rev[j]:
                    k_lo = ceil((lo[j] - tol - x) / two_pi)      # -inf where unlimited
                    k_hi = floor((hi[j] + tol - x) / two_pi)     # +inf where unlimited
                    k = rint((r[i, j] - x) / two_pi)             # half to even, as numpy.round
                    if k < k_lo:
                        k = k_lo
                    if k > k_hi:
                        k = k_hi
                    x = x + k * two_pi
                out[i, j] = x
                if not (x >= lo[j] - tol and x <= hi[j] + tol):
                    ok[i] = 0
    return out_arr, ok_arr.view(np.bool_)
